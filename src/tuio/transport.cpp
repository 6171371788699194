#include "proxygrasp/tuio/transport.h"

#include <algorithm>
#include <arpa/inet.h>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <lo/lo.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <string>
#include <sys/socket.h>
#include <unistd.h>
#include <vector>

namespace pg {

namespace {

// liblo's error handler carries no user data: the receiver polling on this thread, and the last
// error text (for a server that could not be created)
thread_local TuioDecoder* t_pollingDecoder = nullptr;
thread_local std::string t_lastError;

void OnLoError(int num, const char* msg, const char* where) {
  t_lastError = std::string(msg ? msg : "unknown error") + " (liblo " + std::to_string(num) +
                (where ? std::string(", ") + where : std::string()) + ")";
  if (t_pollingDecoder) t_pollingDecoder->CountBadPacket();
}

// liblo's argument pointers point into the datagram, 4-byte aligned, while lo_arg asks for 8:
// read each value by copying its bytes rather than through the union
template <typename T>
T Load(const lo_arg* a) {
  T v;
  std::memcpy(&v, static_cast<const void*>(a), sizeof v);
  return v;
}

OscArg FromLo(char type, const lo_arg* a) {
  const char* text = reinterpret_cast<const char*>(a);
  switch (type) {
    case LO_INT32:
      return OscArg::Int(Load<int32_t>(a));
    case LO_INT64:
      return OscArg::Int64(Load<int64_t>(a));
    case LO_FLOAT:
      return OscArg::Float(Load<float>(a));
    case LO_DOUBLE:
      return OscArg::Double(Load<double>(a));
    case LO_STRING:
      return OscArg::String(text);
    case LO_SYMBOL: {
      OscArg s = OscArg::String(text);
      s.type = 'S';
      return s;
    }
    case LO_TIMETAG: {
      const lo_timetag t = Load<lo_timetag>(a);
      return OscArg::Time({t.sec, t.frac});
    }
    default:
      return OscArg::Other(type);
  }
}

// builds the liblo message of m; false when an argument has a type this cannot send
bool ToLo(const OscMessage& m, lo_message out) {
  for (const OscArg& a : m.args) {
    int r = 0;
    switch (a.type) {
      case 'i':
        r = lo_message_add_int32(out, static_cast<int32_t>(a.i));
        break;
      case 'h':
        r = lo_message_add_int64(out, a.i);
        break;
      case 'f':
        r = lo_message_add_float(out, static_cast<float>(a.f));
        break;
      case 'd':
        r = lo_message_add_double(out, a.f);
        break;
      case 's':
        r = lo_message_add_string(out, a.s.c_str());
        break;
      case 'S':
        r = lo_message_add_symbol(out, a.s.c_str());
        break;
      case 't':
        r = lo_message_add_timetag(out, lo_timetag{a.t.seconds, a.t.fraction});
        break;
      case 'T':
        r = lo_message_add_true(out);
        break;
      case 'F':
        r = lo_message_add_false(out);
        break;
      case 'N':
        r = lo_message_add_nil(out);
        break;
      case 'I':
        r = lo_message_add_infinitum(out);
        break;
      default:
        return false;
    }
    if (r != 0) return false;
  }
  return true;
}

}  // namespace

double TuioClock() {
  using namespace std::chrono;
  return duration<double>(steady_clock::now().time_since_epoch()).count();
}

// ---- receiver ----

struct TuioReceiver::Impl {
  int socket = -1;                                        // the UDP socket listened on
  lo_server server = nullptr;                             // parses the datagrams read from it
  std::vector<char> datagram = std::vector<char>(65536);  // the largest UDP payload
  TuioDecoder* decoder = nullptr;
  double now = 0.0;
  int depth = 0;     // bundle nesting of the datagram being dispatched
  OscBundle bundle;  // the messages of the open bundle, nested ones flattened into it

  static int OnMessage(const char* path, const char* types, lo_arg** argv, int argc, lo_message,
                       void* user) {
    Impl* self = static_cast<Impl*>(user);
    OscMessage m;
    m.address = path ? path : "";
    m.args.reserve(argc);
    for (int k = 0; k < argc; ++k) m.args.push_back(FromLo(types[k], argv[k]));
    if (self->depth > 0) {
      self->bundle.messages.push_back(std::move(m));
    } else {
      self->decoder->Decode(std::span<const OscMessage>(&m, 1), self->now);
    }
    return 0;
  }
  static int OnBundleStart(lo_timetag time, void* user) {
    Impl* self = static_cast<Impl*>(user);
    if (self->depth++ == 0) {
      self->bundle.messages.clear();
      self->bundle.time = {time.sec, time.frac};
    }
    return 0;
  }
  static int OnBundleEnd(void* user) {
    Impl* self = static_cast<Impl*>(user);
    if (self->depth > 0 && --self->depth == 0) self->decoder->Decode(self->bundle, self->now);
    return 0;
  }
};

TuioReceiver::TuioReceiver(const TuioParams& params)
    : m_impl(std::make_unique<Impl>()), m_decoder(params) {}

TuioReceiver::~TuioReceiver() {
  if (!m_impl) return;
  if (m_impl->socket >= 0) close(m_impl->socket);
  if (m_impl->server) lo_server_free(m_impl->server);
}

Result<std::unique_ptr<TuioReceiver>> TuioReceiver::Open(int port, const TuioParams& params) {
  return Open("", port, params);
}

Result<std::unique_ptr<TuioReceiver>> TuioReceiver::Open(const std::string& address, int port,
                                                         const TuioParams& params) {
  if (port < 0 || port > 65535)
    return MakeError({}, "TUIO port must be 0 to 65535 (got " + std::to_string(port) + ")");
  const std::string where =
      (address.empty() ? std::string("port ") : address + ":") + std::to_string(port);
  sockaddr_in bound{};
  bound.sin_family = AF_INET;
  bound.sin_port = htons(static_cast<uint16_t>(port));
  bound.sin_addr.s_addr = htonl(INADDR_ANY);
  if (!address.empty()) {
    // a numeric address, or a name that resolves to one (localhost)
    addrinfo hints{};
    hints.ai_family = AF_INET;
    hints.ai_socktype = SOCK_DGRAM;
    addrinfo* found = nullptr;
    if (getaddrinfo(address.c_str(), nullptr, &hints, &found) != 0 || !found)
      return MakeError(
          {}, "cannot listen for TUIO on " + where + ": no IPv4 address \"" + address + "\"");
    bound.sin_addr = reinterpret_cast<const sockaddr_in*>(found->ai_addr)->sin_addr;
    freeaddrinfo(found);
  }

  std::unique_ptr<TuioReceiver> r(new TuioReceiver(params));
  Impl& impl = *r->m_impl;
  impl.socket = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (impl.socket < 0 ||
      bind(impl.socket, reinterpret_cast<const sockaddr*>(&bound), sizeof bound) != 0)
    return MakeError({}, "cannot listen for TUIO on UDP " + where + ": " + std::strerror(errno));
  // liblo parses and dispatches what the socket reads; its own socket (a free port) is not read
  t_lastError.clear();
  impl.server = lo_server_new_with_proto(nullptr, LO_UDP, OnLoError);
  if (!impl.server)
    return MakeError({}, "cannot set up the OSC parser" +
                             (t_lastError.empty() ? std::string() : ": " + t_lastError));
  // dispatch bundles as they arrive, whatever their time tag says
  lo_server_enable_queue(impl.server, 0, 1);
  lo_server_add_method(impl.server, nullptr, nullptr, &Impl::OnMessage, &impl);
  lo_server_add_bundle_handlers(impl.server, &Impl::OnBundleStart, &Impl::OnBundleEnd, &impl);
  impl.decoder = &r->m_decoder;
  return r;
}

int TuioReceiver::port() const {
  sockaddr_in a{};
  socklen_t size = sizeof a;
  if (getsockname(m_impl->socket, reinterpret_cast<sockaddr*>(&a), &size) != 0) return -1;
  return ntohs(a.sin_port);
}

int TuioReceiver::Poll(double now, int maxPackets) {
  Impl& impl = *m_impl;
  impl.now = now;
  t_pollingDecoder = &m_decoder;
  int read = 0;
  while (read < maxPackets) {
    const ssize_t bytes = recv(impl.socket, impl.datagram.data(), impl.datagram.size(), 0);
    if (bytes < 0) break;  // nothing waiting (EAGAIN), or the socket failed
    ++read;
    if (bytes == 0) {
      m_decoder.CountBadPacket();
      continue;
    }
    lo_server_dispatch_data(impl.server, impl.datagram.data(), static_cast<size_t>(bytes));
    // a bundle that broke off inside is not decoded (liblo reported it as an error)
    if (impl.depth != 0) {
      impl.depth = 0;
      impl.bundle.messages.clear();
    }
  }
  t_pollingDecoder = nullptr;
  m_decoder.Expire(now);
  return read;
}

std::optional<TuioFrame> TuioReceiver::PollFrame(double now, int maxPackets) {
  Poll(now, maxPackets);
  std::vector<TuioFrame> frames = m_decoder.TakeFrames();
  if (frames.empty()) return std::nullopt;
  if (frames.size() == 1) return std::move(frames.front());
  return MergeTuioFrames(frames);
}

std::optional<TuioFrame> TuioReceiver::WaitFrame(double timeout, int maxPackets) {
  const double deadline = TuioClock() + timeout;
  for (;;) {
    Poll(TuioClock(), maxPackets);
    if (m_decoder.HasFrames()) return PollFrame(TuioClock(), maxPackets);
    const double left = deadline - TuioClock();
    if (left <= 0.0) return std::nullopt;
    pollfd waiting{m_impl->socket, POLLIN, 0};
    poll(&waiting, 1, std::max(1, static_cast<int>(std::ceil(left * 1000.0))));
  }
}

// ---- sender ----

struct TuioSender::Impl {
  lo_address address = nullptr;
};

TuioSender::TuioSender() : m_impl(std::make_unique<Impl>()) {}

TuioSender::~TuioSender() {
  if (m_impl && m_impl->address) lo_address_free(m_impl->address);
}

Result<std::unique_ptr<TuioSender>> TuioSender::Open(const std::string& hostPort,
                                                     const TuioEncoderParams& params) {
  const size_t colon = hostPort.rfind(':');
  if (colon == std::string::npos || colon == 0 || colon + 1 == hostPort.size())
    return MakeError({}, "TUIO output must be HOST:PORT (got \"" + hostPort + "\")");
  const std::string host = hostPort.substr(0, colon);
  const std::string portText = hostPort.substr(colon + 1);
  int port = 0;
  for (char ch : portText) {
    if (ch < '0' || ch > '9' || port > 65535) {
      port = -1;
      break;
    }
    port = port * 10 + (ch - '0');
  }
  if (port < 1 || port > 65535)
    return MakeError({}, "TUIO output port must be 1 to 65535 (got \"" + portText + "\")");
  // liblo resolves the host only when it first sends: resolve it here, so that a name that does
  // not resolve is an error now rather than a failed send on every frame
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* found = nullptr;
  if (const int r = getaddrinfo(host.c_str(), portText.c_str(), &hints, &found); r != 0)
    return MakeError({}, "cannot send TUIO to \"" + hostPort + "\": " + gai_strerror(r));
  freeaddrinfo(found);
  std::unique_ptr<TuioSender> s(new TuioSender());
  s->m_encoder.SetParams(params);
  s->m_impl->address = lo_address_new_with_proto(LO_UDP, host.c_str(), portText.c_str());
  if (!s->m_impl->address) return MakeError({}, "cannot send TUIO to \"" + hostPort + "\"");
  return s;
}

MaybeError TuioSender::SendBundle(const OscBundle& bundle) {
  lo_bundle b = lo_bundle_new(lo_timetag{bundle.time.seconds, bundle.time.fraction});
  bool ok = b != nullptr;
  for (const OscMessage& m : bundle.messages) {
    if (!ok) break;
    lo_message lm = lo_message_new();
    if (!ToLo(m, lm) || lo_bundle_add_message(b, m.address.c_str(), lm) != 0) {
      lo_message_free(lm);
      ok = false;
    }
  }
  if (!ok) {
    if (b) lo_bundle_free_recursive(b);
    ++m_sendErrors;
    return MakeError({}, "cannot build an OSC bundle of " + std::to_string(bundle.messages.size()) +
                             " messages");
  }
  const int sent = lo_send_bundle(m_impl->address, b);
  lo_bundle_free_recursive(b);
  if (sent < 0) {
    ++m_sendErrors;
    const char* why = lo_address_errstr(m_impl->address);
    return MakeError({}, std::string("cannot send TUIO: ") + (why ? why : "send failed"));
  }
  return std::nullopt;
}

MaybeError TuioSender::Send(int64_t frame, std::span<const TuioOutContact> contacts) {
  lo_timetag now;
  lo_timetag_now(&now);
  MaybeError first;
  for (const OscBundle& b : m_encoder.Encode(frame, {now.sec, now.frac}, contacts)) {
    MaybeError e = SendBundle(b);
    if (e && !first) first = std::move(e);
  }
  return first;
}

}  // namespace pg
