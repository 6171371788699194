// A live Kinect v1: the source on a device layer (KinectDevice), and that layer through
// libfreenect, depth registered to millimetres (FREENECT_DEPTH_MM).
#include "depth_devices.h"

#include "proxygrasp/sensing/depth_source.h"

#ifdef PROXYGRASP_HAVE_FREENECT
#include <libfreenect.h>
#endif

#include <cstring>
#include <vector>

namespace pg {

namespace {

// the source: what it does when frames stop and when the device comes back, whatever the device
class KinectSource : public FrameSource {
 public:
  KinectSource(std::unique_ptr<KinectDevice> device, int index, std::string spec)
      : m_device(std::move(device)), m_index(index), m_spec(std::move(spec)) {}
  ~KinectSource() override { m_device->Close(); }

  MaybeError Open() {
    m_device->Close();
    m_open = false;
    const std::string why = m_device->Open(m_index);
    if (!why.empty()) return MakeError({m_spec}, why);
    m_open = true;
    return std::nullopt;
  }

  FrameStatus Read(cv::Mat& frame) override {
    if (!m_open) {
      m_lastError = Describe() + ": not open";
      return FrameStatus::kLost;
    }
    // the Kinect sends 30 frames a second: none in a second is a device gone
    constexpr double kWaitSeconds = 1.0;
    if (!m_device->NextFrame(kWaitSeconds, frame)) {
      m_lastError = Describe() + ": the Kinect stopped delivering frames";
      return FrameStatus::kLost;
    }
    m_lastError.clear();
    return FrameStatus::kOk;
  }

  std::string Describe() const override { return "Kinect " + std::to_string(m_index); }
  MaybeError Reopen() override { return Open(); }
  double FrameRate() const override { return 30.0; }

 private:
  std::unique_ptr<KinectDevice> m_device;
  int m_index;
  std::string m_spec;
  bool m_open = false;
};

#ifdef PROXYGRASP_HAVE_FREENECT

class LibfreenectDevice : public KinectDevice {
 public:
  ~LibfreenectDevice() override { Close(); }

  std::string Open(int index) override {
    Close();
    if (freenect_init(&m_context, nullptr) < 0 || !m_context) {
      m_context = nullptr;
      return "libfreenect does not start (no USB access?)";
    }
    freenect_select_subdevices(m_context, FREENECT_DEVICE_CAMERA);
    const int count = freenect_num_devices(m_context);
    if (index >= count || freenect_open_device(m_context, &m_device, index) < 0) {
      m_device = nullptr;
      Close();
      return "no Kinect " + std::to_string(index) + " (" + std::to_string(count < 0 ? 0 : count) +
             " found; is it plugged in and powered?)";
    }
    const freenect_frame_mode mode =
        freenect_find_depth_mode(FREENECT_RESOLUTION_MEDIUM, FREENECT_DEPTH_MM);
    m_buffer.assign(static_cast<size_t>(mode.width) * mode.height, 0);
    m_size = cv::Size(mode.width, mode.height);
    freenect_set_user(m_device, this);
    freenect_set_depth_callback(m_device, &LibfreenectDevice::OnDepth);
    if (freenect_set_depth_mode(m_device, mode) < 0 || freenect_start_depth(m_device) < 0) {
      Close();
      return "cannot start the Kinect's depth stream";
    }
    return "";
  }

  bool NextFrame(double seconds, cv::Mat& depthMm) override {
    if (!m_device) return false;
    // events until a frame arrives, a tenth of a second at a time
    m_fresh = false;
    const int tenths = static_cast<int>(seconds * 10.0 + 0.5);
    for (int i = 0; i < tenths && !m_fresh; ++i) {
      timeval timeout{0, 100000};
      if (freenect_process_events_timeout(m_context, &timeout) < 0) break;
    }
    if (!m_fresh) return false;
    cv::Mat(m_size, CV_16UC1, m_buffer.data()).copyTo(depthMm);
    return true;
  }

  void Close() override {
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

 private:
  static void OnDepth(freenect_device* device, void* depth, uint32_t) {
    auto* self = static_cast<LibfreenectDevice*>(freenect_get_user(device));
    std::memcpy(self->m_buffer.data(), depth, self->m_buffer.size() * sizeof(uint16_t));
    self->m_fresh = true;
  }

  freenect_context* m_context = nullptr;
  freenect_device* m_device = nullptr;
  std::vector<uint16_t> m_buffer;
  cv::Size m_size;
  bool m_fresh = false;
};

#endif

}  // namespace

Result<std::unique_ptr<FrameSource>> OpenKinect(std::unique_ptr<KinectDevice> device, int index,
                                                const std::string& spec) {
  auto source = std::make_unique<KinectSource>(std::move(device), index, spec);
  if (MaybeError s = source->Open()) return *s;
  return std::unique_ptr<FrameSource>(std::move(source));
}

#ifdef PROXYGRASP_HAVE_FREENECT

bool HaveFreenect() {
  return true;
}

Result<std::unique_ptr<FrameSource>> OpenFreenect(int index, const std::string& spec) {
  return OpenKinect(std::make_unique<LibfreenectDevice>(), index, spec);
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
