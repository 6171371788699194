// TUIO over UDP through liblo: a receiver that a caller polls once per frame, and a sender that
// puts a frame of contacts on the wire. The OSC library stays behind these two classes.
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/tuio/decoder.h"
#include "proxygrasp/tuio/encoder.h"

#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace pg {

/// Seconds on a monotonic clock, the clock the receiver's Poll expects.
double TuioClock();

/// Listens for TUIO on a UDP port and decodes what arrives. One datagram is one bundle; a bundle
/// (or a message sent alone) is decoded when it arrives, so frames may span several datagrams.
/// A datagram that is not OSC is counted as a bad packet and dropped.
class TuioReceiver {
 public:
  /// Listens on UDP `port` of every interface; port 0 takes a free port (see port()). An Error
  /// when the port cannot be bound.
  static Result<std::unique_ptr<TuioReceiver>> Open(int port, const TuioParams& params = {});
  /// Listens on UDP `port` of one IPv4 address (a loopback or LAN address, or a name such as
  /// localhost); "" is every interface. An Error when the address does not resolve or the port
  /// cannot be bound there.
  static Result<std::unique_ptr<TuioReceiver>> Open(const std::string& address, int port,
                                                    const TuioParams& params = {});
  ~TuioReceiver();
  TuioReceiver(const TuioReceiver&) = delete;
  TuioReceiver& operator=(const TuioReceiver&) = delete;

  /// The port listened on.
  int port() const;

  /// Decodes every datagram waiting (at most maxPackets, so that a flood cannot hold the caller),
  /// then lifts everything when the stream timed out at `now` (TuioClock() s). Never blocks.
  /// Returns the datagrams read.
  int Poll(double now, int maxPackets = 4096);

  /// Poll, then the frames completed since the last call as one (MergeTuioFrames): the contours
  /// to apply this frame and the sessions that lifted. nullopt when no frame completed.
  std::optional<TuioFrame> PollFrame(double now, int maxPackets = 4096);

  /// PollFrame, waiting up to `timeout` s for a frame to complete (a caller that paces itself by
  /// its input). nullopt when none completed in that time.
  std::optional<TuioFrame> WaitFrame(double timeout, int maxPackets = 4096);

  /// The frames completed since the last call, oldest first.
  std::vector<TuioFrame> TakeFrames() { return m_decoder.TakeFrames(); }

  TuioDecoder& decoder() { return m_decoder; }
  const TuioStats& stats() const { return m_decoder.stats(); }

 private:
  struct Impl;
  explicit TuioReceiver(const TuioParams& params);

  std::unique_ptr<Impl> m_impl;
  TuioDecoder m_decoder;
};

/// Sends frames of contacts as TUIO bundles to one HOST:PORT over UDP.
class TuioSender {
 public:
  /// A sender to "HOST:PORT" (a name or an address; the port 1 to 65535). An Error when the spec
  /// does not parse or the host does not resolve.
  static Result<std::unique_ptr<TuioSender>> Open(const std::string& hostPort,
                                                  const TuioEncoderParams& params = {});
  ~TuioSender();
  TuioSender(const TuioSender&) = delete;
  TuioSender& operator=(const TuioSender&) = delete;

  /// Encodes one frame (TuioEncoder::Encode, time tag now) and sends each bundle. An Error names
  /// the first bundle that could not be sent; the others are still sent.
  MaybeError Send(int64_t frame, std::span<const TuioOutContact> contacts);
  /// Sends one bundle as it is.
  MaybeError SendBundle(const OscBundle& bundle);

  TuioEncoder& encoder() { return m_encoder; }
  /// Bundles that could not be sent, since the start.
  uint64_t sendErrors() const { return m_sendErrors; }

 private:
  struct Impl;
  TuioSender();

  std::unique_ptr<Impl> m_impl;
  TuioEncoder m_encoder;
  uint64_t m_sendErrors = 0;
};

}  // namespace pg
