// OSC values as plain structs, so that TUIO can be decoded and encoded without a socket or an OSC
// library: a message is an address and typed arguments, a bundle a time tag and messages. The
// transport (transport.h) converts them to and from liblo's; tests build them by hand.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace pg {

/// An OSC time tag: seconds since 1900-01-01 in the high 32 bits, the fraction in the low 32.
/// The value 1 means "immediately".
struct OscTimeTag {
  uint32_t seconds = 0;
  uint32_t fraction = 1;

  /// The time tag of t seconds (t >= 0; wrapped modulo 2^32 s).
  static OscTimeTag FromSeconds(double t);
  /// Seconds since the epoch of the tag.
  double ToSeconds() const { return seconds + fraction / 4294967296.0; }

  friend bool operator==(const OscTimeTag&, const OscTimeTag&) = default;
};

/// One OSC argument. `type` is the OSC type tag; the field that holds the value follows it:
/// 'i' (int32) and 'h' (int64) in `i`, 'f' (float32) and 'd' (float64) in `f`, 's' (string) and
/// 'S' (symbol) in `s`, 't' (time tag) in `t`. Any other tag ('b' blob, 'T' true, 'N' nil, ...)
/// carries no value here; the decoder rejects it where it expects a number or a string.
struct OscArg {
  char type = 'N';
  int64_t i = 0;
  double f = 0.0;
  std::string s;
  OscTimeTag t;

  static OscArg Int(int32_t v);
  static OscArg Int64(int64_t v);
  static OscArg Float(float v);
  static OscArg Double(double v);
  static OscArg String(std::string v);
  static OscArg Time(OscTimeTag v);
  /// An argument of a type the decoder does not read (blob, true, nil, ...).
  static OscArg Other(char type);

  /// True for 'i' and 'h'.
  bool IsInt() const { return type == 'i' || type == 'h'; }
  /// True for 'f' and 'd'.
  bool IsFloat() const { return type == 'f' || type == 'd'; }
  /// True for 's' and 'S'.
  bool IsString() const { return type == 's' || type == 'S'; }
};

/// One OSC message: an address pattern and its arguments.
struct OscMessage {
  std::string address;
  std::vector<OscArg> args;

  /// The type tag string without the leading comma, e.g. "siff".
  std::string Types() const;
};

/// An OSC bundle: messages delivered together (nested bundles are flattened into it).
struct OscBundle {
  OscTimeTag time;
  std::vector<OscMessage> messages;
};

/// Bytes of a message on the wire: address, type tags and arguments, each padded to 4 bytes.
std::size_t OscMessageSize(const OscMessage& m);

/// Bytes of a bundle on the wire: "#bundle", the time tag, and a 4-byte size before each message.
std::size_t OscBundleSize(const OscBundle& b);

/// A message as one line for logs and test failures: "/tuio2/alv ii 3 4".
std::string FormatOscMessage(const OscMessage& m);

}  // namespace pg
