// A free UDP port on the loopback address, for the tests that send and receive TUIO.
#pragma once

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

namespace pg::test {

/// A UDP port nobody listens on right now: the kernel's pick for a socket bound to port 0 on the
/// loopback address, closed again. Another process could take it before the test binds it, which
/// on a test machine does not happen in practice.
inline int FreePort() {
  const int fd = socket(AF_INET, SOCK_DGRAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a);
  socklen_t len = sizeof a;
  getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len);
  close(fd);
  return ntohs(a.sin_port);
}

}  // namespace pg::test
