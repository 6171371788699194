#include "proxygrasp/sensing/depth_source.h"

#include "depth_devices.h"
#include "image_list_source.h"

#include <opencv2/imgcodecs.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace pg {

namespace {

namespace fs = std::filesystem;

bool StartsWith(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}

// the depth folders' conversion: 16-bit single-channel images are depth in mm, as they are
std::string DepthImage(const cv::Mat& image, cv::Mat& frame) {
  if (image.empty()) return "cannot read the image (corrupt or not an image)";
  if (image.type() != CV_16UC1)
    return cv::typeToString(image.type()) +
           " image where 16-bit single-channel depth (mm) is expected";
  frame = image;
  return "";
}

// libfreenect's recordings: INDEX.txt names the frames in playback order
class FakenectSource : public FrameSource {
 public:
  FakenectSource(std::string dir, std::vector<std::string> files, double frameRate)
      : m_dir(std::move(dir)), m_files(std::move(files)), m_frameRate(frameRate) {}

  FrameStatus Read(cv::Mat& frame) override {
    if (m_next >= m_files.size()) {
      m_lastError = Describe() + ": no more frames";
      return FrameStatus::kEnd;
    }
    Result<cv::Mat> raw = ReadFakenectDepth(m_files[m_next++]);
    if (!raw.ok()) {
      m_lastError = raw.error().Format();
      return FrameStatus::kError;
    }
    KinectRawToMmImage(raw.value(), frame);
    m_lastError.clear();
    return FrameStatus::kOk;
  }

  std::string Describe() const override { return "fakenect " + m_dir; }
  double FrameRate() const override { return m_frameRate; }

 private:
  std::string m_dir;
  std::vector<std::string> m_files;
  double m_frameRate;
  size_t m_next = 0;
};

// the time stamp fakenect-record puts in a frame's name (d-SECONDS-COUNTER.pgm), or NaN
double FakenectTime(const std::string& name) {
  const size_t dash = name.find('-');
  if (dash == std::string::npos) return std::numeric_limits<double>::quiet_NaN();
  try {
    return std::stod(name.substr(dash + 1));
  } catch (const std::exception&) {
    return std::numeric_limits<double>::quiet_NaN();
  }
}

Result<std::unique_ptr<FrameSource>> OpenFakenect(const std::string& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return MakeError({dir}, "no such folder");
  if (!fs::is_directory(dir, ec)) return MakeError({dir}, "is not a folder");
  const std::string index = (fs::path(dir) / "INDEX.txt").string();
  std::ifstream in(index);
  if (!in) return MakeError({index}, "missing: a fakenect recording lists its frames there");
  // the depth frames in the order INDEX.txt lists them; colour and accelerometer entries skipped
  std::vector<std::string> files;
  std::vector<double> times;
  std::string line;
  int lineNo = 0;
  while (std::getline(in, line)) {
    ++lineNo;
    while (!line.empty() && std::isspace(static_cast<unsigned char>(line.back()))) line.pop_back();
    if (!StartsWith(line, "d-")) continue;
    const std::string path = (fs::path(dir) / line).string();
    if (!fs::is_regular_file(path, ec))
      return MakeError({index, lineNo, 1}, "names " + line + ", which is not in the folder");
    files.push_back(path);
    times.push_back(FakenectTime(line));
  }
  if (files.empty()) return MakeError({index}, "lists no depth frames (d-*.pgm)");
  // the first frame says whether this is a recording at all: a broken one is an error here, a
  // later one a corrupt frame (counted and skipped)
  Result<cv::Mat> first = ReadFakenectDepth(files.front());
  if (!first.ok()) return first.error();
  double rate = 0.0;
  if (files.size() > 1 && std::isfinite(times.front()) && std::isfinite(times.back()) &&
      times.back() > times.front())
    rate = static_cast<double>(files.size() - 1) / (times.back() - times.front());
  return std::unique_ptr<FrameSource>(std::make_unique<FakenectSource>(dir, files, rate));
}

Result<std::unique_ptr<FrameSource>> OpenDepthFolder(const std::string& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return MakeError({dir}, "no such folder");
  if (!fs::is_directory(dir, ec)) return MakeError({dir}, "is not a folder");
  std::vector<std::string> files;
  for (std::string& f : NumberedImages(dir)) {
    std::string ext = fs::path(f).extension().string();
    std::transform(ext.begin(), ext.end(), ext.begin(),
                   [](unsigned char c) { return std::tolower(c); });
    if (ext == ".png" || ext == ".tif" || ext == ".tiff" || ext == ".pgm")
      files.push_back(std::move(f));
  }
  if (files.empty()) return MakeError({dir}, "the folder holds no 16-bit depth images (png)");
  // the first image says whether this is a depth folder at all: an 8-bit folder is an error here,
  // a later bad image is a corrupt frame (counted and skipped)
  cv::Mat first;
  const std::string why = DepthImage(ReadImageUnchanged(files.front()), first);
  if (!why.empty()) return MakeError({files.front()}, why);
  return std::unique_ptr<FrameSource>(
      std::make_unique<ImageListSource>("depth " + dir, std::move(files), DepthImage));
}

}  // namespace

double KinectRawToMm(int raw) {
  if (raw < 0 || raw >= kKinectNoReading) return 0.0;
  const double z = kKinectFitScale * std::tan(raw / kKinectFitSpan + kKinectFitOffset);
  constexpr double kFarthest = 10000.0;  // mm; beyond, the fit is no longer a Kinect's reading
  return z > 0.0 && z <= kFarthest ? z : 0.0;
}

double KinectDisparity(double mm) {
  return (std::atan(mm / kKinectFitScale) - kKinectFitOffset) * kKinectFitSpan;
}

double KinectStepMm(double mm) {
  // d/draw of a tan(raw / b + c): (a / b) sec^2 = (a / b) (1 + (mm / a)^2)
  const double t = mm / kKinectFitScale;
  return kKinectFitScale * (1.0 + t * t) / kKinectFitSpan;
}

int KinectMmToRaw(double mm) {
  if (!(mm > 0.0)) return kKinectNoReading;
  const int r = static_cast<int>(std::lround(KinectDisparity(mm)));
  if (r < 0 || r >= kKinectNoReading) return kKinectNoReading;
  return KinectRawToMm(r) > 0.0 ? r : kKinectNoReading;
}

const std::array<uint16_t, 2048>& KinectRawToMmTable() {
  static const std::array<uint16_t, 2048> table = [] {
    std::array<uint16_t, 2048> t{};
    for (int raw = 0; raw < 2048; ++raw)
      t[raw] = static_cast<uint16_t>(std::lround(KinectRawToMm(raw)));
    return t;
  }();
  return table;
}

void KinectRawToMmImage(const cv::Mat& raw, cv::Mat& mm) {
  CV_Assert(raw.type() == CV_16UC1);
  const std::array<uint16_t, 2048>& table = KinectRawToMmTable();
  mm.create(raw.size(), CV_16UC1);
  for (int y = 0; y < raw.rows; ++y) {
    const uint16_t* in = raw.ptr<uint16_t>(y);
    uint16_t* out = mm.ptr<uint16_t>(y);
    for (int x = 0; x < raw.cols; ++x) out[x] = in[x] < 2048 ? table[in[x]] : 0;
  }
}

Result<cv::Mat> ReadFakenectDepth(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return MakeError({path}, "cannot open the frame");
  // header: P5, width, height, maximum, each after white space (and # comments), then one space
  std::string magic;
  in >> magic;
  if (magic != "P5") return MakeError({path}, "not a binary PGM (no P5 header)");
  long long fields[3] = {0, 0, 0};
  for (long long& f : fields) {
    in >> std::ws;
    while (in.peek() == '#') {
      std::string comment;
      std::getline(in, comment);
      in >> std::ws;
    }
    if (!(in >> f)) return MakeError({path}, "broken PGM header");
  }
  in.get();  // the one white-space character before the pixels
  const long long width = fields[0], height = fields[1], maxValue = fields[2];
  if (width <= 0 || height <= 0 || width > 8192 || height > 8192)
    return MakeError({path}, "PGM of an impossible size " + std::to_string(width) + "x" +
                                 std::to_string(height));
  if (maxValue < 256) return MakeError({path}, "8-bit PGM where 16-bit raw disparity is expected");
  cv::Mat raw(static_cast<int>(height), static_cast<int>(width), CV_16UC1);
  const std::streamsize bytes = static_cast<std::streamsize>(width * height * 2);
  in.read(reinterpret_cast<char*>(raw.data), bytes);
  if (in.gcount() != bytes)
    return MakeError({path}, "truncated: " + std::to_string(in.gcount()) + " of " +
                                 std::to_string(bytes) + " bytes of pixels");
  // little-endian on disk, whatever the PGM standard says (fakenect-record writes memory as is)
  const uint16_t probe = 1;
  if (*reinterpret_cast<const uint8_t*>(&probe) != 1) {
    for (int y = 0; y < raw.rows; ++y) {
      uint16_t* p = raw.ptr<uint16_t>(y);
      for (int x = 0; x < raw.cols; ++x) p[x] = static_cast<uint16_t>((p[x] >> 8) | (p[x] << 8));
    }
  }
  return raw;
}

Result<DepthRecordingWriter> DepthRecordingWriter::Create(const std::string& dir, Format format) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir, ec)) return MakeError({dir}, "cannot create the folder");
  DepthRecordingWriter w;
  w.m_dir = dir;
  w.m_format = format;
  if (format == Format::kFakenect) {
    std::ofstream index((fs::path(dir) / "INDEX.txt").string(), std::ios::trunc);
    if (!index) return MakeError({dir + "/INDEX.txt"}, "cannot write");
  }
  return w;
}

MaybeError DepthRecordingWriter::Write(const cv::Mat& depthMm, double time) {
  if (depthMm.type() != CV_16UC1)
    return MakeError({m_dir}, "depth frames are 16-bit single-channel (got " +
                                  cv::typeToString(depthMm.type()) + ")");
  if (m_format == Format::kDepthPng) {
    char name[32];
    std::snprintf(name, sizeof name, "depth_%06lld.png", static_cast<long long>(m_frames));
    const std::string path = (fs::path(m_dir) / name).string();
    bool ok = false;
    try {
      ok = cv::imwrite(path, depthMm);
    } catch (const cv::Exception&) {
      ok = false;
    }
    if (!ok) return MakeError({path}, "cannot write the image");
  } else {
    // fakenect-record's names: the time in seconds and a counter; raw disparity, little-endian
    char name[64];
    std::snprintf(name, sizeof name, "d-%.6f-%08lld.pgm", 1.0e6 + time,
                  static_cast<long long>(m_frames));
    const std::string path = (fs::path(m_dir) / name).string();
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << "P5 " << depthMm.cols << " " << depthMm.rows << " 65535\n";
    std::vector<uint8_t> row(static_cast<size_t>(depthMm.cols) * 2);
    for (int y = 0; y < depthMm.rows; ++y) {
      const uint16_t* p = depthMm.ptr<uint16_t>(y);
      for (int x = 0; x < depthMm.cols; ++x) {
        const int raw = KinectMmToRaw(p[x]);
        row[2 * x] = static_cast<uint8_t>(raw & 0xff);
        row[2 * x + 1] = static_cast<uint8_t>(raw >> 8);
      }
      out.write(reinterpret_cast<const char*>(row.data()),
                static_cast<std::streamsize>(row.size()));
    }
    if (!out) return MakeError({path}, "cannot write the frame");
    std::ofstream index((fs::path(m_dir) / "INDEX.txt").string(), std::ios::app);
    index << name << "\n";
    if (!index) return MakeError({m_dir + "/INDEX.txt"}, "cannot write");
  }
  ++m_frames;
  return std::nullopt;
}

bool IsDepthSourceSpec(const std::string& spec) {
  return StartsWith(spec, "depth:") || StartsWith(spec, "fakenect:") || StartsWith(spec, "oni:") ||
         spec == "openni" || StartsWith(spec, "openni:") || spec == "kinect" ||
         StartsWith(spec, "kinect:");
}

bool IsLiveDepthSourceSpec(const std::string& spec) {
  return spec == "openni" || StartsWith(spec, "openni:") || spec == "kinect" ||
         StartsWith(spec, "kinect:");
}

Result<std::unique_ptr<FrameSource>> OpenDepthSource(const std::string& spec) {
  if (StartsWith(spec, "depth:")) return OpenDepthFolder(spec.substr(6));
  if (StartsWith(spec, "fakenect:")) return OpenFakenect(spec.substr(9));
  if (StartsWith(spec, "oni:")) {
    const std::string file = spec.substr(4);
    std::error_code ec;
    if (!fs::is_regular_file(file, ec)) return MakeError({file}, "no such ONI file");
    return OpenOpenNi2(file, true, spec);
  }
  if (spec == "openni" || StartsWith(spec, "openni:"))
    return OpenOpenNi2(spec.size() > 7 ? spec.substr(7) : std::string(), false, spec);
  if (spec == "kinect" || StartsWith(spec, "kinect:")) {
    const std::string number = spec.size() > 7 ? spec.substr(7) : "0";
    if (number.empty() || number.size() > 3 ||
        !std::all_of(number.begin(), number.end(), [](unsigned char c) { return std::isdigit(c); }))
      return MakeError({spec}, "the Kinect's number must be a number (kinect, kinect:1, ...)");
    return OpenFreenect(std::stoi(number), spec);
  }
  return MakeError({spec},
                   "not a depth source (depth:DIR, fakenect:DIR, oni:FILE, "
                   "openni[:URI], kinect[:N])");
}

}  // namespace pg
