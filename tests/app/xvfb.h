// A private X server (Xvfb) for the window tests: started on a free display number, stopped when
// the object goes away.
#pragma once

#include <chrono>
#include <csignal>
#include <filesystem>
#include <string>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace pg::test {

/// Path of the Xvfb binary the tests use.
inline constexpr const char* kXvfb = "/usr/bin/Xvfb";

class Xvfb {
 public:
  Xvfb() = default;
  Xvfb(const Xvfb&) = delete;
  Xvfb& operator=(const Xvfb&) = delete;
  ~Xvfb() { Stop(); }

  /// Starts the server on the first free display from a number derived from the pid; false when
  /// none came up within a few seconds.
  bool Start() {
    for (int attempt = 0; attempt < 8; ++attempt) {
      const int number = 200 + static_cast<int>((getpid() * 7 + attempt * 13) % 700);
      const std::string socket = "/tmp/.X11-unix/X" + std::to_string(number);
      const std::string lock = "/tmp/.X" + std::to_string(number) + "-lock";
      if (std::filesystem::exists(socket) || std::filesystem::exists(lock)) continue;
      const std::string display = ":" + std::to_string(number);
      const pid_t pid = fork();
      if (pid < 0) return false;
      if (pid == 0) {
        execl(kXvfb, kXvfb, display.c_str(), "-screen", "0", "1280x1024x24", "-nolisten", "tcp",
              "-noreset", static_cast<char*>(nullptr));
        _exit(127);
      }
      // wait for its socket
      for (int i = 0; i < 100; ++i) {
        if (std::filesystem::exists(socket)) {
          m_pid = pid;
          m_display = display;
          return true;
        }
        int status = 0;
        if (waitpid(pid, &status, WNOHANG) == pid) break;  // it exited: try another number
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
      kill(pid, SIGTERM);
      waitpid(pid, nullptr, 0);
    }
    return false;
  }

  void Stop() {
    if (m_pid <= 0) return;
    kill(m_pid, SIGTERM);
    waitpid(m_pid, nullptr, 0);
    m_pid = -1;
  }

  /// ":N"
  const std::string& display() const { return m_display; }

 private:
  pid_t m_pid = -1;
  std::string m_display;
};

}  // namespace pg::test
