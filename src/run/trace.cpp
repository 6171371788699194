#include "proxygrasp/run/trace.h"

#include "proxygrasp/core/text.h"
#include "proxygrasp/core/units.h"
#include "proxygrasp/run/simulation.h"

#include <cstdio>
#include <filesystem>

namespace pg {

std::string RecordingTraceDir(const std::string& recordingPath) {
  std::filesystem::path p(recordingPath);
  return (p.parent_path() / (p.stem().string() + "_trace")).string();
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

std::string FrameRow(const FrameStats& f, double t) {
  return std::to_string(f.frame) + "," + FormatFixed(t, 6) + "," + std::to_string(f.contacts) +
         "," + std::to_string(f.merges) + "," + std::to_string(f.splits) + "," +
         std::to_string(f.particles) + "," + std::to_string(f.created) + "," +
         std::to_string(f.deleted) + "," + std::to_string(f.bodies) + "," +
         FormatFixed(f.senseMs, 4) + "," + FormatFixed(f.trackMs, 4) + "," +
         FormatFixed(f.proxyMs, 4) + "," + FormatFixed(f.physicsMs, 4) + "," +
         FormatFixed(f.totalMs, 4) + "\n";
}

MaybeError TraceWriter::Open(const std::string& dir, const std::string& videoPath, cv::Size size,
                             double frameRate) {
  Close();
  // the video first: a folder that cannot hold it gets no trace folder made beside it either
  if (!videoPath.empty()) {
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
  m_dir = dir;
  m_frames = 0;
  return std::nullopt;
}

MaybeError TraceWriter::Write(const Simulation& sim) {
  if (!IsOpen()) return MakeError({}, "the trace is not open");
  if (m_recorder.IsOpen()) {
    if (sim.cameraImage().empty())
      return MakeError({},
                       "cannot record camera frames: this input (TUIO contacts or contours) "
                       "brings none");
    if (MaybeError s = m_recorder.Write(sim.cameraImage())) return s;
  }
  // each frame's rows reach the file before the next frame: a run that is stopped keeps them
  if (!(m_objects << ObjectRows(sim) << std::flush)) {
    return MakeError({m_dir + "/objects.csv"}, "cannot write the trace file");
  }
  if (!(m_frameRows << FrameRow(sim.stats(), sim.Time()) << std::flush)) {
    return MakeError({m_dir + "/frames.csv"}, "cannot write the trace file");
  }
  ++m_frames;
  return std::nullopt;
}

MaybeError TraceWriter::Close() {
  m_recorder.Close();
  MaybeError status;
  for (std::ofstream* file : {&m_objects, &m_frameRows}) {
    if (!file->is_open()) continue;
    file->close();
    if (!*file && !status) {
      status = MakeError({m_dir + (file == &m_objects ? "/objects.csv" : "/frames.csv")},
                         "cannot complete the trace file");
    }
  }
  m_objects.clear();
  m_frameRows.clear();
  return status;
}

}  // namespace pg
