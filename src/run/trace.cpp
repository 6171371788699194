#include "proxygrasp/run/trace.h"

#include "proxygrasp/core/text.h"
#include "proxygrasp/core/units.h"
#include "proxygrasp/run/simulation.h"
#include "proxygrasp/sensing/depth_source.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <vector>

namespace pg {

namespace {

// the folder of a depth recording spec (depth:DIR, fakenect:DIR) and its format; false for others
bool DepthRecordingSpec(const std::string& spec, std::string& dir,
                        DepthRecordingWriter::Format& format) {
  for (const auto& [prefix, f] :
       {std::pair{std::string("depth:"), DepthRecordingWriter::Format::kDepthPng},
        std::pair{std::string("fakenect:"), DepthRecordingWriter::Format::kFakenect}}) {
    if (spec.rfind(prefix, 0) == 0) {
      dir = spec.substr(prefix.size());
      format = f;
      return true;
    }
  }
  return false;
}

}  // namespace

std::string RecordingTraceDir(const std::string& recordingPath) {
  std::string dir;
  DepthRecordingWriter::Format format;
  if (DepthRecordingSpec(recordingPath, dir, format)) {
    while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
    return dir + "_trace";
  }
  std::filesystem::path p(recordingPath);
  return (p.parent_path() / (p.stem().string() + "_trace")).string();
}

TraceWriter::TraceWriter() = default;

TraceWriter::~TraceWriter() {
  Close();
}

std::string ObjectRows(const Simulation& sim) {
  // the state after frame n belongs to the time at the end of the frame, Time() after the step
  const std::string frame = std::to_string(sim.Frame() - 1);
  const std::string t = FormatFixed(sim.Time(), 6);
  std::string rows;
  for (int i = 0; i < sim.world().ObjectCount(); ++i) {
    const ObjectState s = sim.world().Object(i);
    rows += frame + "," + t + "," + s.name + "," + FormatFixed(s.pose.pos.x(), 6) + "," +
            FormatFixed(s.pose.pos.y(), 6) + "," + FormatFixed(RadToDeg(s.pose.angle), 6) + "," +
            FormatFixed(s.velocity.x(), 6) + "," + FormatFixed(s.velocity.y(), 6) + "," +
            FormatFixed(RadToDeg(s.angularVelocity), 6) + "," + (s.held ? "1" : "0") + "\n";
  }
  return rows;
}

namespace {

// the mean of the blobs' mean heights as a CSV field: empty when none has heights
template <typename Range, typename BlobOf>
std::string MeanHeightField(const Range& items, BlobOf blobOf) {
  double sum = 0.0;
  int n = 0;
  for (const auto& item : items) {
    const Blob* b = blobOf(item);
    if (!b) continue;
    if (const std::optional<double> h = b->MeanHeight()) {
      sum += *h;
      ++n;
    }
  }
  return n > 0 ? FormatFixed(sum / n, 4) : std::string();
}

}  // namespace

std::string FrameRow(const Simulation& sim) {
  const FrameStats& f = sim.stats();
  const std::string contactHeight = MeanHeightField(sim.contacts().contacts, [](const Contact& c) {
    return c.state == ContactState::kLifted || c.blob.hover ? nullptr : &c.blob;
  });
  const std::vector<Blob>& hover = sim.contours().hover;
  const std::string hoverHeight = MeanHeightField(hover, [](const Blob& b) { return &b; });
  return std::to_string(f.frame) + "," + FormatFixed(sim.Time(), 6) + "," +
         std::to_string(f.contacts) + "," + std::to_string(f.merges) + "," +
         std::to_string(f.splits) + "," + std::to_string(f.particles) + "," +
         std::to_string(f.created) + "," + std::to_string(f.deleted) + "," +
         std::to_string(f.bodies) + "," + contactHeight + "," + std::to_string(hover.size()) + "," +
         hoverHeight + "," + FormatFixed(f.senseMs, 4) + "," + FormatFixed(f.trackMs, 4) + "," +
         FormatFixed(f.proxyMs, 4) + "," + FormatFixed(f.physicsMs, 4) + "," +
         FormatFixed(f.totalMs, 4) + "\n";
}

std::string ContactRows(const Simulation& sim) {
  const std::string frame = std::to_string(sim.stats().frame);
  const std::string t = FormatFixed(sim.Time(), 6);
  std::string rows;
  for (const Contact& c : sim.contacts().contacts) {
    if (c.blob.hover) continue;  // hover regions are not touches (frames.csv counts them)
    const std::optional<double> h = c.blob.MeanHeight();
    rows += frame + "," + t + "," + std::to_string(c.id) + "," +
            kContactStateNames[static_cast<int>(c.state)] + "," +
            FormatFixed(c.blob.centroid.x(), 4) + "," + FormatFixed(c.blob.centroid.y(), 4) + "," +
            FormatFixed(c.blob.area, 4) + "," + (h ? FormatFixed(*h, 4) : std::string()) + "\n";
  }
  return rows;
}

MaybeError TraceWriter::Open(const std::string& dir, const std::string& videoPath, cv::Size size,
                             double frameRate) {
  Close();
  // the video first: a folder that cannot hold it gets no trace folder made beside it either
  std::string depthDir;
  DepthRecordingWriter::Format format;
  if (DepthRecordingSpec(videoPath, depthDir, format)) {
    if (depthDir.empty()) return MakeError({videoPath}, "names no folder for the recording");
    Result<DepthRecordingWriter> writer = DepthRecordingWriter::Create(depthDir, format);
    if (!writer.ok()) return writer.error();
    m_depth = std::make_unique<DepthRecordingWriter>(std::move(writer.value()));
    m_depthSpec = videoPath;
  } else if (!videoPath.empty()) {
    if (MaybeError s = m_recorder.Open(videoPath, size, frameRate)) return s;
  }
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) {
    Close();
    return MakeError({dir}, "cannot create the trace folder: " + ec.message());
  }
  const std::string objectsPath = dir + "/objects.csv";
  const std::string framesPath = dir + "/frames.csv";
  m_objects.open(objectsPath, std::ios::binary | std::ios::trunc);
  if (!(m_objects << kObjectsCsvHeader << "\n")) {
    Close();
    return MakeError({objectsPath}, "cannot write the trace file");
  }
  m_frameRows.open(framesPath, std::ios::binary | std::ios::trunc);
  if (!(m_frameRows << kFramesCsvHeader << "\n")) {
    Close();
    return MakeError({framesPath}, "cannot write the trace file");
  }
  const std::string contactsPath = dir + "/contacts.csv";
  m_contactRows.open(contactsPath, std::ios::binary | std::ios::trunc);
  if (!(m_contactRows << kContactsCsvHeader << "\n")) {
    Close();
    return MakeError({contactsPath}, "cannot write the trace file");
  }
  m_dir = dir;
  m_frames = 0;
  return std::nullopt;
}

MaybeError TraceWriter::Write(const Simulation& sim) {
  if (!IsOpen()) return MakeError({}, "the trace is not open");
  if (m_recorder.IsOpen() || m_depth) {
    if (sim.cameraImage().empty())
      return MakeError({},
                       "cannot record camera frames: this input (TUIO contacts or contours) "
                       "brings none");
    // the frame's own time: frame n began at n frame durations
    const double time =
        static_cast<double>(sim.Frame() - 1) / std::max(sim.params().physics.frameRate, 1e-9);
    if (MaybeError s = WriteCamera(sim.cameraImage(), time)) return s;
  }
  // each frame's rows reach the file before the next frame: a run that is stopped keeps them
  if (!(m_objects << ObjectRows(sim) << std::flush)) {
    return MakeError({m_dir + "/objects.csv"}, "cannot write the trace file");
  }
  if (!(m_frameRows << FrameRow(sim) << std::flush)) {
    return MakeError({m_dir + "/frames.csv"}, "cannot write the trace file");
  }
  if (!(m_contactRows << ContactRows(sim) << std::flush)) {
    return MakeError({m_dir + "/contacts.csv"}, "cannot write the trace file");
  }
  ++m_frames;
  return std::nullopt;
}

MaybeError TraceWriter::WriteCamera(const cv::Mat& image, double time) {
  if (m_depth) {
    if (image.type() != CV_16UC1) {
      return MakeError({m_depthSpec}, "frame " + std::to_string(m_depth->frames()) +
                                          " is not depth (CV_16UC1, mm): a depth recording takes "
                                          "a depth camera's frames ([camera] kind = \"depth\"); "
                                          "record IR frames to a video (.mkv)");
    }
    return m_depth->Write(image, time);
  }
  if (!m_recorder.IsOpen()) return std::nullopt;
  if (image.type() == CV_16UC1) {
    return MakeError({m_recorder.path()}, "frame " + std::to_string(m_recorder.frames()) +
                                              " is depth (CV_16UC1, mm): record a depth "
                                              "camera's frames as depth:DIR or fakenect:DIR");
  }
  return m_recorder.Write(image);
}

MaybeError TraceWriter::Close() {
  m_recorder.Close();
  m_depth.reset();
  MaybeError status;
  for (const auto& [file, name] :
       {std::pair{&m_objects, "/objects.csv"}, std::pair{&m_frameRows, "/frames.csv"},
        std::pair{&m_contactRows, "/contacts.csv"}}) {
    if (file->is_open()) {
      file->close();
      if (!*file && !status) status = MakeError({m_dir + name}, "cannot complete the trace file");
    }
    file->clear();
  }
  return status;
}

}  // namespace pg
