#include "proxygrasp/tuio/touchlib_xml.h"

#include <cassert>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>

namespace pg {

namespace {

// one tag of the document: <name a="v"...>, <name .../> or </name>
struct Tag {
  std::string name;
  std::map<std::string, std::string> attributes;
  bool closing = false;      // </name>
  bool selfClosing = false;  // <name/>
  int line = 0, col = 0;
};

// a scanner over the text that knows the line and column of every position
class Scanner {
 public:
  Scanner(std::string_view text, const std::string& file) : m_text(text), m_file(file) {}

  bool AtEnd() const { return m_pos >= m_text.size(); }

  Error ErrorAt(int line, int col, std::string message) const {
    return MakeError({m_file, line, col}, std::move(message));
  }
  Error ErrorHere(std::string message) const { return ErrorAt(m_line, m_col, std::move(message)); }

  // the next tag, skipping text, the XML declaration, comments and DOCTYPE; false at the end
  Result<bool> Next(Tag& tag) {
    for (;;) {
      while (!AtEnd() && m_text[m_pos] != '<') Advance();
      if (AtEnd()) return false;
      if (Starts("<?")) {
        if (MaybeError e = SkipPast("?>")) return *e;
      } else if (Starts("<!--")) {
        if (MaybeError e = SkipPast("-->")) return *e;
      } else if (Starts("<!")) {
        if (MaybeError e = SkipPast(">")) return *e;
      } else {
        break;
      }
    }
    tag = Tag();
    tag.line = m_line;
    tag.col = m_col;
    Advance();  // '<'
    if (!AtEnd() && m_text[m_pos] == '/') {
      tag.closing = true;
      Advance();
    }
    tag.name = ReadName();
    if (tag.name.empty()) return ErrorAt(tag.line, tag.col, "expected a tag name after '<'");
    // attributes up to '>' or '/>'
    for (;;) {
      SkipSpace();
      if (AtEnd()) return ErrorAt(tag.line, tag.col, "unterminated tag <" + tag.name + ">");
      const char c = m_text[m_pos];
      if (c == '>') {
        Advance();
        return true;
      }
      if (Starts("/>")) {
        Advance();
        Advance();
        tag.selfClosing = true;
        return true;
      }
      const int line = m_line, col = m_col;
      const std::string key = ReadName();
      if (key.empty() || tag.closing)
        return ErrorAt(line, col, std::string("unexpected '") + c + "' in <" + tag.name + ">");
      SkipSpace();
      if (AtEnd() || m_text[m_pos] != '=')
        return ErrorAt(line, col, "attribute " + key + " needs a value (" + key + "=\"...\")");
      Advance();
      SkipSpace();
      if (AtEnd() || (m_text[m_pos] != '"' && m_text[m_pos] != '\''))
        return ErrorHere("attribute " + key + " needs a quoted value");
      const char quote = m_text[m_pos];
      Advance();
      const size_t start = m_pos;
      while (!AtEnd() && m_text[m_pos] != quote) Advance();
      if (AtEnd()) return ErrorAt(line, col, "unterminated value of attribute " + key);
      Result<std::string> value = Unescape(m_text.substr(start, m_pos - start), line, col);
      if (!value) return value.error();
      Advance();
      tag.attributes[key] = std::move(value.value());
    }
  }

 private:
  bool Starts(std::string_view s) const { return m_text.substr(m_pos, s.size()) == s; }

  void Advance() {
    if (m_text[m_pos] == '\n') {
      ++m_line;
      m_col = 1;
    } else {
      ++m_col;
    }
    ++m_pos;
  }

  void SkipSpace() {
    while (!AtEnd() && (m_text[m_pos] == ' ' || m_text[m_pos] == '\t' || m_text[m_pos] == '\n' ||
                        m_text[m_pos] == '\r'))
      Advance();
  }

  MaybeError SkipPast(std::string_view end) {
    const int line = m_line, col = m_col;
    while (!AtEnd() && !Starts(end)) Advance();
    if (AtEnd()) return ErrorAt(line, col, "unterminated markup (no \"" + std::string(end) + "\")");
    for (size_t k = 0; k < end.size(); ++k) Advance();
    return std::nullopt;
  }

  std::string ReadName() {
    const size_t start = m_pos;
    while (!AtEnd()) {
      const char c = m_text[m_pos];
      const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                      c == '_' || c == '-' || c == ':' || c == '.';
      if (!ok) break;
      Advance();
    }
    return std::string(m_text.substr(start, m_pos - start));
  }

  // the five predefined entities and numeric character references below 128
  Result<std::string> Unescape(std::string_view raw, int line, int col) const {
    std::string out;
    out.reserve(raw.size());
    for (size_t k = 0; k < raw.size(); ++k) {
      if (raw[k] != '&') {
        out += raw[k];
        continue;
      }
      const size_t semi = raw.find(';', k);
      if (semi == std::string_view::npos) return ErrorAt(line, col, "'&' without ';' in a value");
      const std::string_view entity = raw.substr(k + 1, semi - k - 1);
      if (entity == "amp")
        out += '&';
      else if (entity == "lt")
        out += '<';
      else if (entity == "gt")
        out += '>';
      else if (entity == "quot")
        out += '"';
      else if (entity == "apos")
        out += '\'';
      else if (entity.size() > 1 && entity[0] == '#') {
        const bool hex = entity[1] == 'x';
        int code = 0;
        const char* first = entity.data() + (hex ? 2 : 1);
        auto [ptr, ec] = std::from_chars(first, entity.data() + entity.size(), code, hex ? 16 : 10);
        if (ec != std::errc() || ptr != entity.data() + entity.size() || code <= 0 || code > 127)
          return ErrorAt(line, col,
                         "unsupported character reference &" + std::string(entity) + ";");
        out += static_cast<char>(code);
      } else {
        return ErrorAt(line, col, "unknown entity &" + std::string(entity) + ";");
      }
      k = semi;
    }
    return out;
  }

  std::string_view m_text;
  const std::string& m_file;
  size_t m_pos = 0;
  int m_line = 1;
  int m_col = 1;
};

// the argument of an <ARGUMENT TYPE VALUE> tag
Result<OscArg> ReadArgument(const Tag& tag, const Scanner& scan) {
  auto type = tag.attributes.find("TYPE");
  if (type == tag.attributes.end() || type->second.size() != 1)
    return scan.ErrorAt(tag.line, tag.col, "ARGUMENT needs a one-letter TYPE");
  const char t = type->second[0];
  auto value = tag.attributes.find("VALUE");
  const bool carriesValue =
      t == 'i' || t == 'h' || t == 'f' || t == 'd' || t == 's' || t == 'S' || t == 't';
  if (!carriesValue) {
    if (t == 'T' || t == 'F' || t == 'N' || t == 'I') return OscArg::Other(t);
    return scan.ErrorAt(
        tag.line, tag.col,
        std::string("unsupported ARGUMENT TYPE \"") + t + "\" (use i h f d s S t T F N I)");
  }
  if (value == tag.attributes.end())
    return scan.ErrorAt(tag.line, tag.col, "ARGUMENT of TYPE " + type->second + " needs a VALUE");
  const std::string& v = value->second;
  if (t == 's' || t == 'S') {
    OscArg a = OscArg::String(v);
    a.type = t;
    return a;
  }
  const char* begin = v.c_str();
  char* end = nullptr;
  errno = 0;
  if (t == 't') {
    // the raw 64-bit time tag, as TIME
    const unsigned long long raw = std::strtoull(begin, &end, 10);
    if (v.empty() || v[0] < '0' || v[0] > '9' || *end != '\0' || errno == ERANGE)
      return scan.ErrorAt(tag.line, tag.col, "VALUE \"" + v + "\" is not a time tag");
    return OscArg::Time(
        {static_cast<uint32_t>(raw >> 32), static_cast<uint32_t>(raw & 0xffffffffu)});
  }
  if (t == 'i' || t == 'h') {
    const long long n = std::strtoll(begin, &end, 10);
    const bool fits = t == 'h' || (n >= INT32_MIN && n <= INT32_MAX);
    if (v.empty() || *end != '\0' || errno == ERANGE || !fits)
      return scan.ErrorAt(tag.line, tag.col,
                          "VALUE \"" + v + "\" is not an int" + (t == 'i' ? "32" : "64"));
    return t == 'i' ? OscArg::Int(static_cast<int32_t>(n)) : OscArg::Int64(n);
  }
  // f or d; NaN and infinities are kept, for the decoder to count
  const double d = std::strtod(begin, &end);
  if (v.empty() || *end != '\0')
    return scan.ErrorAt(tag.line, tag.col, "VALUE \"" + v + "\" is not a number");
  return t == 'f' ? OscArg::Float(static_cast<float>(d)) : OscArg::Double(d);
}

// ---- writing ----

// text for an attribute value in double quotes: the five predefined entities, and control
// characters as numeric references (the reader takes any below 128)
void AppendEscaped(std::string& out, std::string_view text) {
  for (const char c : text) {
    switch (c) {
      case '&':
        out += "&amp;";
        break;
      case '<':
        out += "&lt;";
        break;
      case '>':
        out += "&gt;";
        break;
      case '"':
        out += "&quot;";
        break;
      case '\'':
        out += "&apos;";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20)
          out += "&#" + std::to_string(static_cast<int>(c)) + ";";
        else
          out += c;
    }
  }
}

uint64_t RawTimeTag(OscTimeTag t) {
  return (static_cast<uint64_t>(t.seconds) << 32) | t.fraction;
}

// the VALUE of an argument; false for a type the format does not hold
bool ArgumentValue(const OscArg& a, std::string& value) {
  char buf[40];
  switch (a.type) {
    case 'i':
      // an int32 on the wire, whatever the field holds
      value = std::to_string(static_cast<int32_t>(a.i));
      return true;
    case 'h':
      value = std::to_string(a.i);
      return true;
    case 'f':
      // 9 significant digits tell every float32 apart, 17 every double
      std::snprintf(buf, sizeof buf, "%.9g", static_cast<double>(static_cast<float>(a.f)));
      value = buf;
      return true;
    case 'd':
      std::snprintf(buf, sizeof buf, "%.17g", a.f);
      value = buf;
      return true;
    case 's':
    case 'S':
      value.clear();
      AppendEscaped(value, a.s);
      return a.s.find('\0') == std::string::npos;
    case 't':
      value = std::to_string(RawTimeTag(a.t));
      return true;
    case 'T':
    case 'F':
    case 'N':
    case 'I':
      value.clear();
      return true;
    default:
      return false;
  }
}

}  // namespace

Result<std::vector<OscBundle>> ParseTouchlibXml(std::string_view text, const std::string& file) {
  Scanner scan(text, file);
  std::vector<OscBundle> packets;
  // the open elements that matter: OSCPACKET, then MESSAGE
  bool inPacket = false, inMessage = false;
  int packetLine = 0, packetCol = 0, messageLine = 0, messageCol = 0;
  Tag tag;
  for (;;) {
    Result<bool> more = scan.Next(tag);
    if (!more) return more.error();
    if (!more.value()) break;
    if (tag.name == "OSCPACKET") {
      if (tag.closing) {
        if (!inPacket || inMessage)
          return scan.ErrorAt(tag.line, tag.col, "</OSCPACKET> without its <OSCPACKET>");
        inPacket = false;
        continue;
      }
      if (inPacket)
        return scan.ErrorAt(tag.line, tag.col,
                            "OSCPACKET inside the OSCPACKET at line " + std::to_string(packetLine));
      OscBundle b;
      if (auto time = tag.attributes.find("TIME"); time != tag.attributes.end()) {
        char* end = nullptr;
        errno = 0;
        const unsigned long long raw = std::strtoull(time->second.c_str(), &end, 10);
        if (time->second.empty() || *end != '\0' || errno == ERANGE)
          return scan.ErrorAt(tag.line, tag.col, "TIME \"" + time->second + "\" is not a time tag");
        b.time = {static_cast<uint32_t>(raw >> 32), static_cast<uint32_t>(raw & 0xffffffffu)};
      }
      packets.push_back(std::move(b));
      inPacket = !tag.selfClosing;
      packetLine = tag.line;
      packetCol = tag.col;
    } else if (tag.name == "MESSAGE") {
      if (tag.closing) {
        if (!inMessage) return scan.ErrorAt(tag.line, tag.col, "</MESSAGE> without its <MESSAGE>");
        inMessage = false;
        continue;
      }
      if (!inPacket) return scan.ErrorAt(tag.line, tag.col, "MESSAGE outside an OSCPACKET");
      if (inMessage)
        return scan.ErrorAt(tag.line, tag.col,
                            "MESSAGE inside the MESSAGE at line " + std::to_string(messageLine));
      auto name = tag.attributes.find("NAME");
      if (name == tag.attributes.end() || name->second.empty() || name->second[0] != '/')
        return scan.ErrorAt(tag.line, tag.col, "MESSAGE needs a NAME starting with '/'");
      packets.back().messages.push_back(OscMessage{name->second, {}});
      inMessage = !tag.selfClosing;
      messageLine = tag.line;
      messageCol = tag.col;
    } else if (tag.name == "ARGUMENT") {
      if (tag.closing) continue;
      if (!inMessage) return scan.ErrorAt(tag.line, tag.col, "ARGUMENT outside a MESSAGE");
      Result<OscArg> arg = ReadArgument(tag, scan);
      if (!arg) return arg.error();
      packets.back().messages.back().args.push_back(std::move(arg.value()));
    }
    // any other element (the OSCPackets root, comments' neighbours) is structure only
  }
  if (inMessage) return scan.ErrorAt(messageLine, messageCol, "MESSAGE is never closed");
  if (inPacket) return scan.ErrorAt(packetLine, packetCol, "OSCPACKET is never closed");
  return packets;
}

Result<std::vector<OscBundle>> ReadTouchlibXml(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return MakeError({path, 0, 0}, "cannot open the TUIO recording");
  std::ostringstream text;
  text << in.rdbuf();
  return ParseTouchlibXml(text.str(), path);
}

MaybeError TouchlibXmlWriter::Open(const std::string& path, const std::string& address, int port) {
  assert(!IsOpen() && "close the recording before opening another");
  m_path = path;
  m_packets = 0;
  m_failed = false;
  m_errno = 0;
  m_file = std::fopen(path.c_str(), "wb");
  if (!m_file)
    return MakeError({path},
                     std::string("cannot create the TUIO recording: ") + std::strerror(errno));
  m_packetStart = "  <OSCPACKET ADDRESS=\"";
  AppendEscaped(m_packetStart, address);
  m_packetStart += "\" PORT=\"" + std::to_string(port) + "\" TIME=\"";
  if (!Write("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<OSCPackets>\n")) {
    MaybeError e = Close();
    return e;
  }
  return std::nullopt;
}

bool TouchlibXmlWriter::Write(const std::string& text) {
  if (std::fwrite(text.data(), 1, text.size(), m_file) == text.size()) return true;
  if (!m_failed) m_errno = errno;
  m_failed = true;
  return false;
}

MaybeError TouchlibXmlWriter::Append(const OscBundle& bundle) {
  if (!IsOpen()) return MakeError({m_path}, "the TUIO recording is not open");
  // the whole packet first, so that a bundle the format cannot hold leaves nothing behind
  std::string text = m_packetStart + std::to_string(RawTimeTag(bundle.time)) + "\">\n";
  std::string value;
  for (const OscMessage& m : bundle.messages) {
    text += "    <MESSAGE NAME=\"";
    AppendEscaped(text, m.address);
    text += "\">\n";
    for (size_t k = 0; k < m.args.size(); ++k) {
      const OscArg& a = m.args[k];
      if (!ArgumentValue(a, value)) {
        const bool nul = a.type == 's' || a.type == 'S';
        return MakeError({m_path}, m.address + " argument " + std::to_string(k) + ": " +
                                       (nul ? std::string("a string holding a NUL byte")
                                            : std::string("type '") + a.type + "'") +
                                       " cannot be recorded (types i h f d s S t T F N I)");
      }
      text += "      <ARGUMENT TYPE=\"";
      text += a.type;
      text += '"';
      if (a.type != 'T' && a.type != 'F' && a.type != 'N' && a.type != 'I')
        text += " VALUE=\"" + value + '"';
      text += "/>\n";
    }
    text += "    </MESSAGE>\n";
  }
  text += "  </OSCPACKET>\n";
  if (!Write(text))
    return MakeError({m_path},
                     std::string("cannot write the TUIO recording: ") + std::strerror(m_errno));
  ++m_packets;
  return std::nullopt;
}

MaybeError TouchlibXmlWriter::Close() {
  if (!m_file) return std::nullopt;
  Write("</OSCPackets>\n");
  if (std::fflush(m_file) != 0 && !m_failed) {
    m_errno = errno;
    m_failed = true;
  }
  if (std::fclose(m_file) != 0 && !m_failed) {
    m_errno = errno;
    m_failed = true;
  }
  m_file = nullptr;
  if (m_failed)
    return MakeError({m_path},
                     std::string("cannot complete the TUIO recording: ") + std::strerror(m_errno));
  return std::nullopt;
}

}  // namespace pg
