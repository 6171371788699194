#include "proxygrasp/sensing/frame_source.h"

#include "proxygrasp/sensing/depth_source.h"

#include <opencv2/core/utils/logger.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <opencv2/videoio/registry.hpp>

#include <algorithm>
#include <cctype>
#include <filesystem>

namespace pg {

namespace {

namespace fs = std::filesystem;

// converts whatever a capture or file delivered into 8-bit grey; false when it cannot
bool ToGrey(const cv::Mat& in, cv::Mat& out) {
  if (in.empty()) return false;
  cv::Mat eight;
  if (in.depth() == CV_8U)
    eight = in;
  else if (in.depth() == CV_16U)
    in.convertTo(eight, CV_8U, 1.0 / 256.0);
  else
    return false;
  switch (eight.channels()) {
    case 1:
      out = eight.clone();
      return true;
    case 3:
      cv::cvtColor(eight, out, cv::COLOR_BGR2GRAY);
      return true;
    case 4:
      cv::cvtColor(eight, out, cv::COLOR_BGRA2GRAY);
      return true;
    default:
      return false;
  }
}

// OpenCV logs its own warnings when a device is missing; our message says it better
class QuietOpenCv {
 public:
  QuietOpenCv() : m_old(cv::utils::logging::getLogLevel()) {
    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  }
  ~QuietOpenCv() { cv::utils::logging::setLogLevel(m_old); }
  QuietOpenCv(const QuietOpenCv&) = delete;
  QuietOpenCv& operator=(const QuietOpenCv&) = delete;

 private:
  cv::utils::logging::LogLevel m_old;
};

#ifdef __linux__
constexpr int kCameraApi = cv::CAP_V4L2;
#else
constexpr int kCameraApi = cv::CAP_ANY;
#endif

class CameraSource : public FrameSource {
 public:
  CameraSource(int index, std::string path) : m_index(index), m_path(std::move(path)) {}

  MaybeError Open() {
    QuietOpenCv quiet;
    try {
      m_capture.release();
      // V4L2 directly on Linux: probing every backend (FireWire, gphoto2 over libusb, ...) is slow
      // and those libraries leak on the way
      const bool ok = m_path.empty() ? m_capture.open(m_index, kCameraApi)
                                     : m_capture.open(m_path, cv::CAP_V4L2);
      if (!ok || !m_capture.isOpened())
        return MakeError({Describe()}, "cannot open the camera (is it connected, and free?)");
    } catch (const cv::Exception& e) {
      return MakeError({Describe()}, std::string("cannot open the camera: ") + e.what());
    }
    return std::nullopt;
  }

  FrameStatus Read(cv::Mat& frame) override {
    cv::Mat raw;
    try {
      QuietOpenCv quiet;
      if (!m_capture.isOpened() || !m_capture.read(raw) || raw.empty()) {
        m_lastError = Describe() + ": the camera stopped delivering frames";
        return FrameStatus::kLost;
      }
    } catch (const cv::Exception& e) {
      m_lastError = Describe() + ": the camera failed: " + e.what();
      return FrameStatus::kLost;
    }
    if (!ToGrey(raw, frame)) {
      m_lastError = Describe() + ": unsupported frame format " + cv::typeToString(raw.type());
      return FrameStatus::kError;
    }
    m_lastError.clear();
    return FrameStatus::kOk;
  }

  std::string Describe() const override {
    return m_path.empty() ? "camera " + std::to_string(m_index) : "camera " + m_path;
  }
  MaybeError Reopen() override { return Open(); }
  double FrameRate() const override {
    return m_capture.isOpened() ? m_capture.get(cv::CAP_PROP_FPS) : 0.0;
  }

 private:
  int m_index;
  std::string m_path;
  cv::VideoCapture m_capture;
};

class VideoSource : public FrameSource {
 public:
  explicit VideoSource(std::string path) : m_path(std::move(path)) {}

  MaybeError Open() {
    QuietOpenCv quiet;
    try {
      // FFmpeg reads every common container; other backends only when it is missing
      const int api =
          cv::videoio_registry::hasBackend(cv::CAP_FFMPEG) ? cv::CAP_FFMPEG : cv::CAP_ANY;
      if (!m_capture.open(m_path, api) || !m_capture.isOpened())
        return MakeError({m_path}, "cannot open as a video (unknown format or codec)");
    } catch (const cv::Exception& e) {
      return MakeError({m_path}, std::string("cannot open as a video: ") + e.what());
    }
    return std::nullopt;
  }

  FrameStatus Read(cv::Mat& frame) override {
    cv::Mat raw;
    try {
      if (!m_capture.read(raw) || raw.empty()) {
        m_lastError = Describe() + ": end of video";
        return FrameStatus::kEnd;
      }
    } catch (const cv::Exception& e) {
      m_lastError = Describe() + ": cannot decode a frame: " + e.what();
      return FrameStatus::kError;
    }
    if (!ToGrey(raw, frame)) {
      m_lastError = Describe() + ": unsupported frame format " + cv::typeToString(raw.type());
      return FrameStatus::kError;
    }
    m_lastError.clear();
    return FrameStatus::kOk;
  }

  std::string Describe() const override { return "video " + m_path; }
  double FrameRate() const override { return m_capture.get(cv::CAP_PROP_FPS); }

 private:
  std::string m_path;
  cv::VideoCapture m_capture;
};

class FolderSource : public FrameSource {
 public:
  FolderSource(std::string dir, std::vector<std::string> files)
      : m_dir(std::move(dir)), m_files(std::move(files)) {}

  FrameStatus Read(cv::Mat& frame) override {
    if (m_next >= m_files.size()) {
      m_lastError = Describe() + ": no more images";
      return FrameStatus::kEnd;
    }
    const std::string& file = m_files[m_next++];
    cv::Mat raw;
    try {
      raw = cv::imread(file, cv::IMREAD_UNCHANGED);
    } catch (const cv::Exception&) {
      raw.release();
    }
    if (!ToGrey(raw, frame)) {
      m_lastError = file + ": cannot read as an 8-bit image";
      return FrameStatus::kError;
    }
    m_lastError.clear();
    return FrameStatus::kOk;
  }

  std::string Describe() const override {
    return (m_files.size() == 1 && m_files[0] == m_dir ? "image " : "folder ") + m_dir;
  }

 private:
  std::string m_dir;
  std::vector<std::string> m_files;
  size_t m_next = 0;
};

bool StartsWith(const std::string& s, const std::string& prefix) {
  return s.rfind(prefix, 0) == 0;
}

// the last run of digits in a file name, or -1
long long LastNumber(const std::string& name) {
  int end = static_cast<int>(name.size()) - 1;
  while (end >= 0 && !std::isdigit(static_cast<unsigned char>(name[end]))) --end;
  if (end < 0) return -1;
  int begin = end;
  while (begin > 0 && std::isdigit(static_cast<unsigned char>(name[begin - 1]))) --begin;
  const std::string digits = name.substr(begin, std::min(end - begin + 1, 18));
  return std::stoll(digits);
}

}  // namespace

bool IsImageFile(const std::string& path) {
  static const char* const kExtensions[] = {".png", ".jpg",  ".jpeg", ".bmp",
                                            ".tif", ".tiff", ".pgm",  ".ppm"};
  std::string ext = fs::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  return std::find(std::begin(kExtensions), std::end(kExtensions), ext) != std::end(kExtensions);
}

std::vector<std::string> NumberedImages(const std::string& dir) {
  std::vector<std::pair<long long, std::string>> found;
  std::error_code ec;
  for (const fs::directory_entry& e : fs::directory_iterator(dir, ec)) {
    if (!e.is_regular_file()) continue;
    if (!IsImageFile(e.path().string())) continue;
    const std::string stem = e.path().stem().string();
    found.emplace_back(LastNumber(stem), e.path().string());
  }
  std::sort(found.begin(), found.end());
  std::vector<std::string> files;
  for (auto& f : found) files.push_back(std::move(f.second));
  return files;
}

SyntheticSource::SyntheticSource(std::string name, const SyntheticCameraParams& camera,
                                 const TableParams& table, ShapeScript script, int64_t frameCount,
                                 double frameRate)
    : m_name(std::move(name)),
      m_camera(camera, table),
      m_script(std::move(script)),
      m_frameCount(frameCount),
      m_frameRate(frameRate) {}

FrameStatus SyntheticSource::Read(cv::Mat& frame) {
  if (m_frameCount >= 0 && m_next >= m_frameCount) {
    m_lastError = Describe() + ": end of script";
    return FrameStatus::kEnd;
  }
  if (!m_script(m_next, m_shapes)) {
    m_lastError = Describe() + ": end of script";
    return FrameStatus::kEnd;
  }
  ++m_next;
  frame = m_camera.Render(m_shapes);
  m_lastError.clear();
  return FrameStatus::kOk;
}

Result<std::unique_ptr<FrameSource>> OpenFrameSource(const std::string& spec) {
  using Ptr = std::unique_ptr<FrameSource>;
  if (spec.empty())
    return MakeError({}, "no input given (camera:N, a video, a folder or synthetic:NAME)");

  // depth cameras and their recordings (sensing/depth_source.h)
  if (IsDepthSourceSpec(spec)) return OpenDepthSource(spec);

  // built-in synthetic demo scenes
  if (StartsWith(spec, "synthetic:")) {
    const std::string name = spec.substr(10);
    const TableParams table;
    std::vector<ContactShape> probe;
    if (!DemoScene(name, 0, table, probe))
      return MakeError({spec}, "unknown synthetic scene '" + name + "' (known: fingers, hands)");
    constexpr int64_t kDemoFrames = 600;  // 10 s at 60 Hz
    auto script = [name, table](int64_t frame, std::vector<ContactShape>& shapes) {
      return DemoScene(name, frame, table, shapes);
    };
    return Ptr(std::make_unique<SyntheticSource>(spec, SyntheticCameraParams{}, table, script,
                                                 kDemoFrames));
  }

  // cameras by index or device path
  if (StartsWith(spec, "camera:") || StartsWith(spec, "/dev/video")) {
    int index = -1;
    std::string path;
    if (StartsWith(spec, "camera:")) {
      const std::string number = spec.substr(7);
      if (number.empty() || number.size() > 6 ||
          !std::all_of(number.begin(), number.end(),
                       [](unsigned char c) { return std::isdigit(c); }))
        return MakeError({spec}, "camera index must be a number (camera:0, camera:1, ...)");
      index = std::stoi(number);
    } else {
      path = spec;
      if (!fs::exists(path)) return MakeError({spec}, "no such camera device");
    }
    auto camera = std::make_unique<CameraSource>(index, path);
    if (MaybeError s = camera->Open()) return MakeError({spec}, s->message);
    return Ptr(std::move(camera));
  }

  // folders of numbered images
  std::string path = spec;
  bool wantFolder = false, wantVideo = false;
  if (StartsWith(spec, "folder:")) {
    path = spec.substr(7);
    wantFolder = true;
  } else if (StartsWith(spec, "video:")) {
    path = spec.substr(6);
    wantVideo = true;
  }
  std::error_code ec;
  if (!fs::exists(path, ec)) return MakeError({path}, "no such file or directory");
  if (fs::is_directory(path, ec)) {
    if (wantVideo) return MakeError({path}, "is a directory, not a video file");
    std::vector<std::string> files = NumberedImages(path);
    if (files.empty())
      return MakeError({path}, "the folder holds no image files (png, jpg, bmp, tif, pgm, ppm)");
    return Ptr(std::make_unique<FolderSource>(path, std::move(files)));
  }
  if (wantFolder) return MakeError({path}, "is not a directory");
  // one image file: a folder of one image
  if (!wantVideo && IsImageFile(path))
    return Ptr(std::make_unique<FolderSource>(path, std::vector<std::string>{path}));
  auto video = std::make_unique<VideoSource>(path);
  if (MaybeError s = video->Open()) return *s;
  return Ptr(std::move(video));
}

}  // namespace pg
