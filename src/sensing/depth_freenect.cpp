// A live Kinect v1 through libfreenect: depth registered to millimetres (FREENECT_DEPTH_MM).
#include "depth_devices.h"

#include "proxygrasp/sensing/depth_source.h"

#ifdef PROXYGRASP_HAVE_FREENECT
#include <libfreenect.h>
#endif

#include <cstring>
#include <vector>

namespace pg {

#ifdef PROXYGRASP_HAVE_FREENECT

bool HaveFreenect() {
  return true;
}

namespace {

class FreenectSource : public FrameSource {
 public:
  FreenectSource(int index, std::string spec) : m_index(index), m_spec(std::move(spec)) {}
  ~FreenectSource() override { Close(); }

  MaybeError Open() {
    Close();
    if (freenect_init(&m_context, nullptr) < 0 || !m_context)
      return MakeError({m_spec}, "libfreenect does not start (no USB access?)");
    freenect_select_subdevices(m_context, FREENECT_DEVICE_CAMERA);
    const int count = freenect_num_devices(m_context);
    if (m_index >= count || freenect_open_device(m_context, &m_device, m_index) < 0) {
      m_device = nullptr;
      Close();
      return MakeError({m_spec}, "no Kinect " + std::to_string(m_index) + " (" +
                                     std::to_string(count < 0 ? 0 : count) +
                                     " found; is it plugged in and powered?)");
    }
    const freenect_frame_mode mode =
        freenect_find_depth_mode(FREENECT_RESOLUTION_MEDIUM, FREENECT_DEPTH_MM);
    m_buffer.assign(static_cast<size_t>(mode.width) * mode.height, 0);
    m_size = cv::Size(mode.width, mode.height);
    freenect_set_user(m_device, this);
    freenect_set_depth_callback(m_device, &FreenectSource::OnDepth);
    if (freenect_set_depth_mode(m_device, mode) < 0 || freenect_start_depth(m_device) < 0) {
      Close();
      return MakeError({m_spec}, "cannot start the Kinect's depth stream");
    }
    return std::nullopt;
  }

  FrameStatus Read(cv::Mat& frame) override {
    if (!m_device) {
      m_lastError = Describe() + ": not open";
      return FrameStatus::kLost;
    }
    // events until a frame arrives, for at most a second (the Kinect sends 30 a second)
    m_fresh = false;
    timeval timeout{0, 100000};
    for (int i = 0; i < 10 && !m_fresh; ++i) {
      if (freenect_process_events_timeout(m_context, &timeout) < 0) break;
    }
    if (!m_fresh) {
      m_lastError = Describe() + ": the Kinect stopped delivering frames";
      return FrameStatus::kLost;
    }
    cv::Mat(m_size, CV_16UC1, m_buffer.data()).copyTo(frame);
    m_lastError.clear();
    return FrameStatus::kOk;
  }

  std::string Describe() const override { return "Kinect " + std::to_string(m_index); }
  MaybeError Reopen() override { return Open(); }
  double FrameRate() const override { return 30.0; }

 private:
  static void OnDepth(freenect_device* device, void* depth, uint32_t) {
    auto* self = static_cast<FreenectSource*>(freenect_get_user(device));
    std::memcpy(self->m_buffer.data(), depth, self->m_buffer.size() * sizeof(uint16_t));
    self->m_fresh = true;
  }

  void Close() {
    if (m_device) {
      freenect_stop_depth(m_device);
      freenect_close_device(m_device);
      m_device = nullptr;
    }
    if (m_context) {
      freenect_shutdown(m_context);
      m_context = nullptr;
    }
  }

  int m_index;
  std::string m_spec;
  freenect_context* m_context = nullptr;
  freenect_device* m_device = nullptr;
  std::vector<uint16_t> m_buffer;
  cv::Size m_size;
  bool m_fresh = false;
};

}  // namespace

Result<std::unique_ptr<FrameSource>> OpenFreenect(int index, const std::string& spec) {
  auto source = std::make_unique<FreenectSource>(index, spec);
  if (MaybeError s = source->Open()) return *s;
  return std::unique_ptr<FrameSource>(std::move(source));
}

#else

bool HaveFreenect() {
  return false;
}

Result<std::unique_ptr<FrameSource>> OpenFreenect(int, const std::string& spec) {
  return MakeError({spec}, "not built with libfreenect (install libfreenect-dev and rebuild)");
}

#endif

}  // namespace pg
