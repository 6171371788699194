// Recorded TUIO streams in touchlib's XML form: each OSC packet written out as an <OSCPACKET>
// element holding <MESSAGE NAME="/tuio/2Dcur"> elements, each holding <ARGUMENT TYPE="f"
// VALUE="0.32"/> elements. Read with a small tag scanner into the OSC structs the decoder takes,
// and written, one packet at a time, by TouchlibXmlWriter (proxygrasp's own TUIO recordings).
#pragma once

#include "proxygrasp/core/error.h"
#include "proxygrasp/tuio/osc.h"

#include <cstdint>
#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

namespace pg {

/// The packets of a touchlib XML recording, in file order, one bundle each (TIME, the raw 64-bit
/// OSC time tag, becomes the bundle's time). Argument types i, h, f, d, s, S and t (VALUE the raw
/// 64-bit time tag) keep their values; T, F, N and I carry none. An Error reads
/// "file:line:col: message"; nothing is half-read. `file` names the text in errors.
Result<std::vector<OscBundle>> ParseTouchlibXml(std::string_view text, const std::string& file);

/// ParseTouchlibXml on the contents of a file; an Error when it cannot be read.
Result<std::vector<OscBundle>> ReadTouchlibXml(const std::string& path);

/// Writes OSC bundles as a touchlib XML recording that ReadTouchlibXml reads back equal: one
/// <OSCPACKET> per bundle, streamed to the file as it comes (nothing of the recording is kept in
/// memory). TIME is the bundle's raw 64-bit time tag (seconds << 32 | fraction); f arguments are
/// written with 9 significant digits and d with 17, so both read back exactly; strings are
/// escaped. A recording of nothing is still a document (<OSCPackets></OSCPackets>).
class TouchlibXmlWriter {
 public:
  TouchlibXmlWriter() = default;
  TouchlibXmlWriter(const TouchlibXmlWriter&) = delete;
  TouchlibXmlWriter& operator=(const TouchlibXmlWriter&) = delete;
  ~TouchlibXmlWriter() { Close(); }

  /// Creates (or empties) the file and starts the document. `address` and `port` fill every
  /// packet's ADDRESS and PORT, the sender as touchlib noted it (the reader ignores them). An
  /// Error naming the path when the file cannot be created (its folder is not created); on error
  /// nothing is open.
  MaybeError Open(const std::string& path, const std::string& address = "127.0.0.1",
                  int port = 3333);

  /// Appends one bundle as an <OSCPACKET>. An argument of a type the format does not hold (only
  /// i h f d s S t T F N I) or a string holding a NUL byte is an Error naming the message, and
  /// nothing of the bundle is written; a failed write is an Error naming the path.
  MaybeError Append(const OscBundle& bundle);

  /// Ends the document, flushes and closes the file. Safe to call twice. An Error naming the path
  /// when the file could not be completed (this or any earlier write failed).
  MaybeError Close();

  bool IsOpen() const { return m_file != nullptr; }
  /// The file written to.
  const std::string& path() const { return m_path; }
  /// Packets appended since Open.
  int64_t packets() const { return m_packets; }

 private:
  // writes text; false (and remembered) when the write failed
  bool Write(const std::string& text);

  std::FILE* m_file = nullptr;
  std::string m_path;
  std::string m_packetStart;  // '<OSCPACKET ADDRESS=".." PORT=".." TIME="'
  int64_t m_packets = 0;
  bool m_failed = false;
  int m_errno = 0;  // of the first failed write
};

}  // namespace pg
