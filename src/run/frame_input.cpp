#include "proxygrasp/run/frame_input.h"

#include "proxygrasp/run/simulation.h"

namespace pg {

FrameInput FrameInput::Script() {
  return FrameInput(Kind::kScript);
}

FrameInput FrameInput::Shapes() {
  return FrameInput(Kind::kShapes);
}

FrameInput FrameInput::Contours() {
  return FrameInput(Kind::kContours);
}

Result<FrameInput> FrameInput::Open(const std::string& spec, bool keepMissing) {
  Result<std::unique_ptr<FrameSource>> source = OpenFrameSource(spec);
  if (source.ok()) return FromSource(std::move(source.value()), spec);
  if (!keepMissing) return source.error();
  FrameInput input(Kind::kSource);
  input.m_spec = spec;
  input.m_lastError = source.error().Format();
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
    case Kind::kSource: {
      if (!m_source) {
        if (m_lastError.empty()) m_lastError = m_spec + ": no input";
        return FrameStatus::kLost;
      }
      const FrameStatus read = m_peeked ? FrameStatus::kOk : m_source->Read(m_frame);
      m_peeked = false;
      if (read != FrameStatus::kOk) {
        m_lastError = read == FrameStatus::kEnd ? "" : m_source->LastError();
        return read;
      }
      const int64_t index = m_framesRead++;
      const cv::Size expected = sim.CameraSize();
      if (m_frame.size() != expected) {
        m_lastError = m_source->Describe() + ": frame " + std::to_string(index) + ": frame is " +
                      std::to_string(m_frame.cols) + "x" + std::to_string(m_frame.rows) +
                      ", expected " + std::to_string(expected.width) + "x" +
                      std::to_string(expected.height) + " ([camera] width and height)";
        return FrameStatus::kError;
      }
      status = sim.StepImage(m_frame);
      break;
    }
  }
  if (status) return *status;
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
    case Kind::kSource:
      break;
  }
  return m_source ? m_source->Describe() : m_spec;
}

}  // namespace pg
