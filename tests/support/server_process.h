#pragma once
// A policy server run as a child process for the tests of the remote-policy clients: the
// reference servers of tests/remote/servers (with /usr/bin/python3, which sees Debian's
// python3-* packages) or `hribench serve`. The server prints its port on its first line
// ("PORT 41234" or "... at ws://127.0.0.1:41234"); the process is stopped (SIGTERM, then SIGKILL)
// when the object goes away. Nothing waits forever: the first line must come within 10 s.

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace hribench::testing {

class ServerProcess {
 public:
  // Runs argv[0] with argv; waits for the line with the port.
  explicit ServerProcess(const std::vector<std::string>& argv) {
    int fds[2];
    if (pipe(fds) != 0) throw std::runtime_error("pipe failed");
    pid_ = fork();
    if (pid_ == 0) {
      dup2(fds[1], STDOUT_FILENO);
      close(fds[0]);
      close(fds[1]);
      std::vector<char*> args;
      for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
      args.push_back(nullptr);
      execv(args[0], args.data());
      _exit(127);
    }
    close(fds[1]);
    out_ = fds[0];
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    std::string line;
    while (line.find('\n') == std::string::npos) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - std::chrono::steady_clock::now());
      pollfd p{out_, POLLIN, 0};
      if (left.count() <= 0 || poll(&p, 1, static_cast<int>(left.count())) <= 0) break;
      char c;
      if (read(out_, &c, 1) != 1) break;
      line += c;
    }
    first_line_ = line;
    const size_t digits_end = line.find_last_of("0123456789");
    if (digits_end == std::string::npos) {
      stop();
      throw std::runtime_error("the server printed no port: '" + line + "'");
    }
    size_t begin = digits_end;
    while (begin > 0 && line[begin - 1] >= '0' && line[begin - 1] <= '9') --begin;
    port_ = std::stoi(line.substr(begin, digits_end - begin + 1));
  }
  ~ServerProcess() { stop(); }
  ServerProcess(const ServerProcess&) = delete;
  ServerProcess& operator=(const ServerProcess&) = delete;

  int port() const { return port_; }
  const std::string& first_line() const { return first_line_; }
  // True once the process has exited (e.g. a server told to die).
  bool exited() {
    if (pid_ <= 0) return true;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      return true;
    }
    return false;
  }

  void stop() {
    if (pid_ > 0) {
      kill(pid_, SIGTERM);
      for (int i = 0; i < 50; ++i) {
        int status = 0;
        if (waitpid(pid_, &status, WNOHANG) == pid_) {
          pid_ = -1;
          break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
      if (pid_ > 0) {
        kill(pid_, SIGKILL);
        waitpid(pid_, nullptr, 0);
        pid_ = -1;
      }
    }
    if (out_ >= 0) {
      close(out_);
      out_ = -1;
    }
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
  int port_ = 0;
  std::string first_line_;
};

// The reference server tests/remote/servers/NAME with extra arguments.
inline std::vector<std::string> reference_server(const std::string& name, std::vector<std::string> args) {
  std::vector<std::string> argv = {"/usr/bin/python3", std::string(HRIBENCH_SOURCE_DIR) + "/tests/remote/servers/" + name};
  argv.insert(argv.end(), args.begin(), args.end());
  return argv;
}

}  // namespace hribench::testing
