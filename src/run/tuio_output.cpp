#include "proxygrasp/run/tuio_output.h"

#include "proxygrasp/tuio/touchlib_xml.h"
#include "proxygrasp/tuio/transport.h"

#include <utility>
#include <vector>

namespace pg {

namespace {

constexpr const char* kFilePrefix = "file:";

}  // namespace

std::vector<TuioOutContact> ToTuioOutContacts(const ContactSet& contacts) {
  std::vector<TuioOutContact> out;
  for (const Contact& c : contacts.contacts) {
    // hover regions tracked for measured placement are not touches
    if (c.state == ContactState::kLifted || c.blob.hover) continue;
    TuioOutContact& o = out.emplace_back();
    o.id = c.id;
    o.centroid = c.blob.centroid;
    o.contour.reserve(static_cast<size_t>(c.blob.contour.cols()));
    for (Eigen::Index k = 0; k < c.blob.contour.cols(); ++k)
      o.contour.push_back(c.blob.contour.col(k));
    // a depth camera's contact: its mean height over the outline
    o.height = c.blob.MeanHeight();
  }
  return out;
}

TuioOutput::TuioOutput(const TuioEncoderParams& params) : m_encoder(params) {}

TuioOutput::~TuioOutput() = default;

Result<std::unique_ptr<TuioOutput>> TuioOutput::Open(const std::string& spec,
                                                     const TuioEncoderParams& params) {
  std::unique_ptr<TuioOutput> out(new TuioOutput(params));
  out->m_spec = spec;
  // file:PATH, a recording
  if (spec.rfind(kFilePrefix, 0) == 0) {
    const std::string path = spec.substr(std::string(kFilePrefix).size());
    if (path.empty())
      return MakeError({}, "a TUIO recording needs a path: file:PATH (got \"file:\")");
    out->m_writer = std::make_unique<TouchlibXmlWriter>();
    if (MaybeError e = out->m_writer->Open(path)) return *e;
    return out;
  }
  // HOST:PORT over UDP
  if (spec.find(':') == std::string::npos)
    return MakeError({}, "TUIO output must be HOST:PORT or file:PATH (got \"" + spec + "\")");
  Result<std::unique_ptr<TuioSender>> sender = TuioSender::Open(spec, params);
  if (!sender.ok()) return sender.error();
  out->m_sender = std::move(sender.value());
  return out;
}

MaybeError TuioOutput::Send(const Simulation& sim) {
  // the simulation's table and camera size, which a run's parameters may change
  const LevelParams& p = sim.params();
  TuioEncoderParams params = m_encoder.params();
  params.table = p.table;
  params.sensorWidth = p.camera.width;
  params.sensorHeight = p.camera.height;
  m_encoder.SetParams(params);

  // a restarted run: lift the old run's contacts, and go on counting frames and time after it
  const FrameStats& stats = sim.stats();
  MaybeError first;
  if (m_anySent && stats.frame <= m_lastSimFrame) {
    if (m_lastHadContacts)
      first = SendFrame(m_lastFrameId + 1, m_lastTime + sim.FrameDuration(), {});
    m_frameOffset = m_lastFrameId + 1 - stats.frame;
    m_timeOffset = m_lastTime + sim.FrameDuration() - stats.time;
  }
  m_lastSimFrame = stats.frame;

  // the contacts still on the table, as they were tracked
  const std::vector<TuioOutContact> contacts = ToTuioOutContacts(sim.contacts());
  MaybeError e = SendFrame(stats.frame + m_frameOffset, stats.time + m_timeOffset, contacts);
  if (!first) first = std::move(e);
  return first;
}

MaybeError TuioOutput::SendFrame(int64_t frame, double time,
                                 std::span<const TuioOutContact> contacts) {
  MaybeError first;
  for (const OscBundle& b : m_encoder.Encode(frame, OscTimeTag::FromSeconds(time), contacts)) {
    MaybeError e = m_writer ? m_writer->Append(b) : m_sender->SendBundle(b);
    if (!e) continue;
    ++m_sendErrors;
    if (!first) first = std::move(e);
  }
  ++m_frames;
  m_anySent = true;
  m_lastFrameId = frame;
  m_lastTime = time;
  m_lastHadContacts = !contacts.empty();
  return first;
}

MaybeError TuioOutput::Close() {
  return m_writer ? m_writer->Close() : std::nullopt;
}

std::string TuioOutput::Status() const {
  std::string status = "tuio out " + m_spec + ": " + std::to_string(m_frames) + " frames, " +
                       std::to_string(m_sendErrors) + (m_writer ? " write" : " send") + " errors";
  if (const uint64_t dropped = m_encoder.stats().droppedContacts; dropped > 0)
    status += ", " + std::to_string(dropped) + " contacts dropped";
  return status;
}

}  // namespace pg
