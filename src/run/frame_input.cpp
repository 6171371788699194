#include "proxygrasp/run/frame_input.h"

#include "proxygrasp/level/level.h"
#include "proxygrasp/run/simulation.h"

#include <charconv>

namespace pg {

FrameInput FrameInput::Script() {
  return FrameInput(Kind::kScript);
}

Result<FrameInput> FrameInput::ForLevel(const Level& level) {
  const pg::Script& script = level.script;
  if (script.tuioBundles) return Tuio(TuioStream::Replay(*script.tuioBundles, script.tuio));
  if (script.recording.empty()) return Script();
  Result<FrameInput> input = Open("video:" + script.recording);
  if (!input.ok()) return MakeError({script.recording}, input.error().Format());
  return input;
}

FrameInput FrameInput::Shapes() {
  return FrameInput(Kind::kShapes);
}

FrameInput FrameInput::Contours() {
  return FrameInput(Kind::kContours);
}

namespace {

// tuio:PORT or tuio:ADDRESS:PORT
Result<std::unique_ptr<TuioStream>> ListenTuio(const std::string& spec) {
  const std::string rest = spec.substr(5);
  const size_t colon = rest.rfind(':');
  const std::string address = colon == std::string::npos ? std::string() : rest.substr(0, colon);
  const std::string portText = colon == std::string::npos ? rest : rest.substr(colon + 1);
  int port = -1;
  const auto [end, ec] = std::from_chars(portText.data(), portText.data() + portText.size(), port);
  if (ec != std::errc() || end != portText.data() + portText.size() || port < 0 || port > 65535 ||
      (colon != std::string::npos && address.empty()))
    return MakeError(
        {}, "expected tuio:PORT or tuio:ADDRESS:PORT, the port 0 to 65535 (got \"" + spec + "\")");
  return TuioStream::Listen(address, port);
}

}  // namespace

Result<FrameInput> FrameInput::Open(const std::string& spec, bool keepMissing) {
  if (spec.rfind("tuio:", 0) == 0) {
    Result<std::unique_ptr<TuioStream>> stream = ListenTuio(spec);
    if (!stream.ok()) return stream.error();
    return Tuio(std::move(stream.value()));
  }
  Result<std::unique_ptr<FrameSource>> source = OpenFrameSource(spec);
  if (source.ok()) return FromSource(std::move(source.value()), spec);
  if (!keepMissing) return source.error();
  FrameInput input(Kind::kSource);
  input.m_spec = spec;
  input.m_lastError = source.error().Format();
  return input;
}

FrameInput FrameInput::Tuio(std::unique_ptr<TuioStream> stream) {
  FrameInput input(Kind::kTuio);
  input.m_spec = stream->Describe();
  input.m_tuio = std::move(stream);
  return input;
}

FrameInput FrameInput::FromSource(std::unique_ptr<FrameSource> source, std::string spec) {
  FrameInput input(Kind::kSource);
  input.m_source = std::move(source);
  input.m_spec = std::move(spec);
  return input;
}

void FrameInput::SetShapes(std::span<const ContactShape> shapes) {
  m_shapes.assign(shapes.begin(), shapes.end());
}

void FrameInput::SetContours(ContourFrame contours) {
  m_contours = std::move(contours);
}

Result<FrameStatus> FrameInput::Step(Simulation& sim) {
  m_lastError.clear();
  MaybeError status;
  switch (m_kind) {
    case Kind::kScript:
      status = sim.StepScript();
      break;
    case Kind::kShapes:
      status = sim.StepShapes(m_shapes);
      break;
    case Kind::kContours:
      status = sim.StepContours(m_contours);
      break;
    case Kind::kTuio: {
      TuioParams tuio;
      tuio.table = sim.params().table;
      const std::optional<TuioFrame> frame = m_tuio->Next(sim.Time(), sim.FrameDuration(), tuio);
      status = sim.StepContacts(
          m_tuioTracker.Step(frame ? &*frame : nullptr, sim.params().sensing.spacing));
      break;
    }
    case Kind::kSource: {
      if (!m_source) {
        if (m_lastError.empty()) m_lastError = m_spec + ": no input";
        return FrameStatus::kLost;
      }
      const FrameStatus read = m_peeked ? FrameStatus::kOk : m_source->Read(m_frame);
      m_peeked = false;
      if (read != FrameStatus::kOk) {
        m_lastError = read == FrameStatus::kEnd ? "" : m_source->LastError();
        if (read == FrameStatus::kError) {
          // a frame that could not be read still takes its place: later frames keep their numbers
          ++m_framesRead;
          ++m_skippedFrames;
        }
        return read;
      }
      const int64_t index = m_framesRead++;
      const cv::Size expected = sim.CameraSize();
      if (m_frame.size() != expected) {
        m_lastError = m_source->Describe() + ": frame " + std::to_string(index) + ": frame is " +
                      std::to_string(m_frame.cols) + "x" + std::to_string(m_frame.rows) +
                      ", expected " + std::to_string(expected.width) + "x" +
                      std::to_string(expected.height) + " ([camera] width and height)";
        ++m_skippedFrames;
        return FrameStatus::kError;
      }
      status = sim.StepImage(m_frame);
      break;
    }
  }
  if (status) {
    ++m_skippedFrames;
    return *status;
  }
  return FrameStatus::kOk;
}

FrameStatus FrameInput::Peek() {
  if (m_kind != Kind::kSource) return FrameStatus::kOk;
  if (m_peeked) return FrameStatus::kOk;
  if (!m_source) {
    if (m_lastError.empty()) m_lastError = m_spec + ": no input";
    return FrameStatus::kLost;
  }
  const FrameStatus read = m_source->Read(m_frame);
  m_lastError = read == FrameStatus::kOk || read == FrameStatus::kEnd ? "" : m_source->LastError();
  m_peeked = read == FrameStatus::kOk;
  return read;
}

MaybeError FrameInput::Reconnect() {
  if (m_kind != Kind::kSource) return std::nullopt;
  m_peeked = false;
  m_framesRead = 0;
  if (m_source && !m_source->Reopen()) {
    m_lastError.clear();
    return std::nullopt;
  }
  Result<std::unique_ptr<FrameSource>> opened = OpenFrameSource(m_spec);
  if (!opened.ok()) {
    m_lastError = opened.error().Format();
    return opened.error();
  }
  m_source = std::move(opened.value());
  m_lastError.clear();
  return std::nullopt;
}

std::string FrameInput::Describe() const {
  switch (m_kind) {
    case Kind::kScript:
      return "script";
    case Kind::kShapes:
      return "shapes";
    case Kind::kContours:
      return "contours";
    case Kind::kTuio:
      return m_tuio->Describe();
    case Kind::kSource:
      break;
  }
  return m_source ? m_source->Describe() : m_spec;
}

}  // namespace pg
