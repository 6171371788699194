// OpenNI2 devices and ONI recordings (its file driver plays a recording with no device).
#include "depth_devices.h"

#include "proxygrasp/sensing/depth_source.h"

#ifdef PROXYGRASP_HAVE_OPENNI2
#include <OpenNI.h>
#endif

#include <algorithm>
#include <mutex>

namespace pg {

#ifdef PROXYGRASP_HAVE_OPENNI2

bool HaveOpenNi2() {
  return true;
}

namespace {

// OpenNI2's last error, on one line
std::string LastOpenNiError() {
  std::string text = openni::OpenNI::getExtendedError();
  for (char& c : text)
    if (c == '\n' || c == '\t') c = ' ';
  const size_t begin = text.find_first_not_of(' ');
  const size_t end = text.find_last_not_of(' ');
  return begin == std::string::npos ? std::string("no reason given")
                                    : text.substr(begin, end - begin + 1);
}

// OpenNI2 is initialized once per process and never shut down (its drivers keep threads)
MaybeError InitializeOpenNi(const std::string& spec) {
  static std::once_flag once;
  static openni::Status status = openni::STATUS_OK;
  static std::string message;
  std::call_once(once, [] {
    status = openni::OpenNI::initialize();
    if (status != openni::STATUS_OK) message = LastOpenNiError();
  });
  if (status != openni::STATUS_OK) return MakeError({spec}, "OpenNI2 does not start: " + message);
  return std::nullopt;
}

class OpenNiSource : public FrameSource {
 public:
  OpenNiSource(std::string uri, bool file, std::string spec)
      : m_uri(std::move(uri)), m_file(file), m_spec(std::move(spec)) {}
  ~OpenNiSource() override { Close(); }

  MaybeError Open() {
    Close();
    if (MaybeError s = InitializeOpenNi(m_spec)) return s;
    const char* uri = m_uri.empty() ? openni::ANY_DEVICE : m_uri.c_str();
    if (m_device.open(uri) != openni::STATUS_OK) {
      const std::string what = m_file ? "cannot play the ONI file" : "no OpenNI2 device";
      return MakeError({m_file ? m_uri : m_spec}, what + " (" + LastOpenNiError() + ")");
    }
    if (!m_device.hasSensor(openni::SENSOR_DEPTH))
      return MakeError({m_file ? m_uri : m_spec}, m_file ? "the ONI file has no depth stream"
                                                         : "the device has no depth sensor");
    if (m_depth.create(m_device, openni::SENSOR_DEPTH) != openni::STATUS_OK)
      return MakeError({m_spec},
                       std::string("cannot create the depth stream: ") + LastOpenNiError());
    if (m_file) {
      // One frame per read, as fast as the pipeline takes them. The recording's end is its frame
      // count where the file gives one, and the player is left to loop: a player that stops at
      // the end spins over its stream list, unlocked, until the stream is destroyed, and
      // destroying it then races that loop (a crash under load). Looping, the player instead
      // waits for the next read's trigger, holding no reference to the list. Without a frame
      // count the end is the player's own, with no looping.
      openni::PlaybackControl* playback = m_device.getPlaybackControl();
      if (playback) {
        playback->setSpeed(-1.0f);
        m_frameCount = std::max(playback->getNumberOfFrames(m_depth), 0);
        playback->setRepeatEnabled(m_frameCount > 0);
      }
    }
    if (m_depth.start() != openni::STATUS_OK)
      return MakeError({m_spec},
                       std::string("cannot start the depth stream: ") + LastOpenNiError());
    const openni::VideoMode mode = m_depth.getVideoMode();
    m_fps = mode.getFps();
    m_open = true;
    m_read = 0;
    return std::nullopt;
  }

  FrameStatus Read(cv::Mat& frame) override {
    if (!m_open) {
      m_lastError = Describe() + ": not open";
      return FrameStatus::kLost;
    }
    if (m_file && m_frameCount > 0 && m_read >= m_frameCount) {
      m_lastError = Describe() + ": end of recording";
      return FrameStatus::kEnd;
    }
    openni::VideoStream* streams[] = {&m_depth};
    int ready = -1;
    constexpr int kTimeoutMs = 2000;  // a live device delivers 30 frames a second
    if (openni::OpenNI::waitForAnyStream(streams, 1, &ready, kTimeoutMs) != openni::STATUS_OK) {
      if (m_file) {
        m_lastError = Describe() + ": end of recording";
        return FrameStatus::kEnd;
      }
      m_lastError = Describe() + ": the device stopped delivering frames";
      return FrameStatus::kLost;
    }
    openni::VideoFrameRef ref;
    if (m_depth.readFrame(&ref) != openni::STATUS_OK || !ref.isValid()) {
      m_lastError = Describe() + ": cannot read a frame: " + LastOpenNiError();
      return m_file ? FrameStatus::kError : FrameStatus::kLost;
    }
    ++m_read;
    const openni::PixelFormat format = ref.getVideoMode().getPixelFormat();
    const cv::Mat view(ref.getHeight(), ref.getWidth(), CV_16UC1, const_cast<void*>(ref.getData()),
                       static_cast<size_t>(ref.getStrideInBytes()));
    if (format == openni::PIXEL_FORMAT_DEPTH_1_MM) {
      view.copyTo(frame);
    } else if (format == openni::PIXEL_FORMAT_DEPTH_100_UM) {
      view.convertTo(frame, CV_16U, 0.1);
    } else {
      m_lastError = Describe() + ": depth in an unsupported pixel format " +
                    std::to_string(static_cast<int>(format));
      return FrameStatus::kError;
    }
    m_lastError.clear();
    return FrameStatus::kOk;
  }

  std::string Describe() const override {
    if (m_file) return "ONI file " + m_uri;
    return m_uri.empty() ? "OpenNI2 device" : "OpenNI2 device " + m_uri;
  }
  MaybeError Reopen() override {
    if (m_file) return MakeError({m_uri}, "a recording cannot be reopened");
    return Open();
  }
  double FrameRate() const override { return m_fps; }

 private:
  void Close() {
    if (m_depth.isValid()) {
      m_depth.stop();
      m_depth.destroy();
    }
    if (m_device.isValid()) m_device.close();
    m_open = false;
  }

  std::string m_uri;
  bool m_file;
  std::string m_spec;
  openni::Device m_device;
  openni::VideoStream m_depth;
  bool m_open = false;
  int m_frameCount = 0;  // frames of a recording's depth stream (0 = unknown)
  int m_read = 0;
  double m_fps = 0.0;
};

}  // namespace

Result<std::unique_ptr<FrameSource>> OpenOpenNi2(const std::string& uri, bool file,
                                                 const std::string& spec) {
  auto source = std::make_unique<OpenNiSource>(uri, file, spec);
  if (MaybeError s = source->Open()) return *s;
  return std::unique_ptr<FrameSource>(std::move(source));
}

#else

bool HaveOpenNi2() {
  return false;
}

Result<std::unique_ptr<FrameSource>> OpenOpenNi2(const std::string&, bool,
                                                 const std::string& spec) {
  return MakeError({spec}, "not built with OpenNI2 (install libopenni2-dev and rebuild)");
}

#endif

}  // namespace pg
