#include "proxygrasp/tuio/osc.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pg {

namespace {

// bytes of an OSC string with its terminating zero, padded to 4
std::size_t PaddedStringSize(std::size_t length) {
  return (length + 4) & ~std::size_t(3);
}

}  // namespace

OscTimeTag OscTimeTag::FromSeconds(double t) {
  OscTimeTag tag;
  if (!std::isfinite(t) || t < 0.0) t = 0.0;
  const double whole = std::floor(t);
  tag.seconds = static_cast<uint32_t>(std::fmod(whole, 4294967296.0));
  tag.fraction = static_cast<uint32_t>(std::min((t - whole) * 4294967296.0, 4294967295.0));
  return tag;
}

OscArg OscArg::Int(int32_t v) {
  OscArg a;
  a.type = 'i';
  a.i = v;
  return a;
}

OscArg OscArg::Int64(int64_t v) {
  OscArg a;
  a.type = 'h';
  a.i = v;
  return a;
}

OscArg OscArg::Float(float v) {
  OscArg a;
  a.type = 'f';
  a.f = v;
  return a;
}

OscArg OscArg::Double(double v) {
  OscArg a;
  a.type = 'd';
  a.f = v;
  return a;
}

OscArg OscArg::String(std::string v) {
  OscArg a;
  a.type = 's';
  a.s = std::move(v);
  return a;
}

OscArg OscArg::Time(OscTimeTag v) {
  OscArg a;
  a.type = 't';
  a.t = v;
  return a;
}

OscArg OscArg::Other(char type) {
  OscArg a;
  a.type = type;
  return a;
}

std::string OscMessage::Types() const {
  std::string types;
  types.reserve(args.size());
  for (const OscArg& a : args) types.push_back(a.type);
  return types;
}

std::size_t OscMessageSize(const OscMessage& m) {
  // address, then ",types", then the arguments
  std::size_t size = PaddedStringSize(m.address.size()) + PaddedStringSize(1 + m.args.size());
  for (const OscArg& a : m.args) {
    switch (a.type) {
      case 'i':
      case 'f':
      case 'c':
      case 'r':
      case 'm':
        size += 4;
        break;
      case 'h':
      case 'd':
      case 't':
        size += 8;
        break;
      case 's':
      case 'S':
        size += PaddedStringSize(a.s.size());
        break;
      default:  // T, F, N, I carry no data; blobs are not built here
        break;
    }
  }
  return size;
}

std::size_t OscBundleSize(const OscBundle& b) {
  std::size_t size = 8 + 8;  // "#bundle\0" and the time tag
  for (const OscMessage& m : b.messages) size += 4 + OscMessageSize(m);
  return size;
}

std::string FormatOscMessage(const OscMessage& m) {
  std::string out = m.address + " " + m.Types();
  char buffer[64];
  for (const OscArg& a : m.args) {
    out += ' ';
    if (a.IsInt()) {
      std::snprintf(buffer, sizeof buffer, "%lld", static_cast<long long>(a.i));
      out += buffer;
    } else if (a.IsFloat()) {
      std::snprintf(buffer, sizeof buffer, "%.9g", a.f);
      out += buffer;
    } else if (a.IsString()) {
      out += '"' + a.s + '"';
    } else if (a.type == 't') {
      std::snprintf(buffer, sizeof buffer, "%08x.%08x", a.t.seconds, a.t.fraction);
      out += buffer;
    } else {
      out += '-';
    }
  }
  return out;
}

}  // namespace pg
