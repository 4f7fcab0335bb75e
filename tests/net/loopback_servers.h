// Real servers on loopback for the network tests: nginx (started on a free port with a generated
// configuration, no root needed: its prefix, pid, logs and temporary folders are the test's) and
// the fault-injecting proxy (tests/net/fault_proxy.py, Python 3 standard library). Both end with
// the object. A missing nginx or python3 is a test failure naming the Debian package, never a
// skip.
#pragma once

#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

namespace parallax::test {

inline std::string readWholeFile(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A port nothing listens on now (the kernel's choice for port 0).
inline int freeLoopbackPort() {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t length = sizeof address;
  if (fd < 0 || ::bind(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) != 0 ||
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&address), &length) != 0) {
    if (fd >= 0) ::close(fd);
    throw std::runtime_error("no free loopback port");
  }
  ::close(fd);
  return ntohs(address.sin_port);
}

inline bool acceptsConnections(int port) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  address.sin_port = htons(std::uint16_t(port));
  const bool ok =
      fd >= 0 && ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0;
  if (fd >= 0) ::close(fd);
  return ok;
}

// A child process, stopped with SIGTERM (then SIGKILL) and reaped when the object ends.
class ChildProcess {
 public:
  ChildProcess() = default;
  // execv(program, args) with stdout into a pipe (readLine) and stderr into `stderr_file`.
  ChildProcess(const std::string& program, const std::vector<std::string>& args,
               const std::filesystem::path& stderr_file) {
    int out[2];
    if (::pipe2(out, O_CLOEXEC) != 0) throw std::runtime_error("pipe failed");
    std::vector<char*> argv;
    for (const std::string& arg : args) argv.push_back(const_cast<char*>(arg.c_str()));
    argv.push_back(nullptr);
    pid_ = ::fork();
    if (pid_ < 0) throw std::runtime_error("fork failed");
    if (pid_ == 0) {
      ::dup2(out[1], 1);
      const int err = ::open(stderr_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (err >= 0) ::dup2(err, 2);
      ::execvp(program.c_str(), argv.data());
      ::_exit(127);
    }
    ::close(out[1]);
    out_ = out[0];
  }
  ~ChildProcess() { stop(); }
  ChildProcess(ChildProcess&& other) noexcept
      : pid_(std::exchange(other.pid_, -1)), out_(std::exchange(other.out_, -1)) {}
  ChildProcess& operator=(ChildProcess&& other) noexcept {
    stop();
    pid_ = std::exchange(other.pid_, -1);
    out_ = std::exchange(other.out_, -1);
    return *this;
  }

  bool running() {
    if (pid_ <= 0) return false;
    int status = 0;
    if (::waitpid(pid_, &status, WNOHANG) == pid_) {
      pid_ = -1;
      return false;
    }
    return true;
  }

  // A line of the child's stdout, or empty after `timeout`.
  std::string readLine(std::chrono::milliseconds timeout) {
    std::string line;
    const auto deadline = std::chrono::steady_clock::now() + timeout;
    while (std::chrono::steady_clock::now() < deadline) {
      pollfd p{out_, POLLIN, 0};
      if (::poll(&p, 1, 50) <= 0) continue;
      char c = 0;
      if (::read(out_, &c, 1) != 1) break;
      if (c == '\n') return line;
      line += c;
    }
    return {};
  }

  void stop() {
    if (pid_ > 0) {
      ::kill(pid_, SIGTERM);
      for (int i = 0; i < 100; ++i) {
        int status = 0;
        if (::waitpid(pid_, &status, WNOHANG) == pid_) {
          pid_ = -1;
          break;
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
      if (pid_ > 0) {
        ::kill(pid_, SIGKILL);
        ::waitpid(pid_, nullptr, 0);
        pid_ = -1;
      }
    }
    if (out_ >= 0) ::close(out_);
    out_ = -1;
  }

 private:
  pid_t pid_ = -1;
  int out_ = -1;
};

// One line of nginx's access log (the format the configuration below writes).
struct AccessLine {
  std::string method, path;
  int status = 0;
  std::uint64_t bytes = 0;
  std::string range;     // "-" when none
  std::string protocol;  // "HTTP/1.1", "HTTP/2.0"
};

inline std::string nginxProgram() {
  if (const char* env = std::getenv("PARALLAX_NGINX"); env && *env) return env;
  for (const char* candidate : {"/usr/sbin/nginx", "/usr/local/sbin/nginx"}) {
    if (::access(candidate, X_OK) == 0) return candidate;
  }
  throw std::runtime_error(
      "nginx not found (/usr/sbin/nginx): install the Debian package 'nginx' "
      "(scripts/install-deps.sh) or name it in PARALLAX_NGINX");
}

class Nginx {
 public:
  struct Options {
    std::filesystem::path root;                      // served at "/"
    std::filesystem::path tls_certificate, tls_key;  // both set: https with http2
    std::string server_config;                       // more directives for the server block
  };

  Nginx(const std::filesystem::path& work_dir, const Options& options) : dir_(work_dir) {
    std::filesystem::create_directories(dir_);
    tls_ = !options.tls_certificate.empty();
    std::string last_error;
    for (int attempt = 0; attempt < 5; ++attempt) {
      port_ = freeLoopbackPort();
      do {
        status_port_ = freeLoopbackPort();
      } while (status_port_ == port_);
      writeConfig(options);
      std::filesystem::remove(dir_ / "access.log");
      process_ = ChildProcess(nginxProgram(),
                              {"nginx", "-p", dir_.string(), "-c", (dir_ / "nginx.conf").string(),
                               "-e", (dir_ / "error.log").string()},
                              dir_ / "stderr.txt");
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
      while (std::chrono::steady_clock::now() < deadline && process_.running()) {
        if (acceptsConnections(port_)) return;
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
      }
      last_error = readWholeFile(dir_ / "error.log") + readWholeFile(dir_ / "stderr.txt");
      process_.stop();
    }
    throw std::runtime_error("nginx did not start: " + last_error);
  }

  int port() const { return port_; }
  std::string url(const std::string& path) const {
    return std::string(tls_ ? "https" : "http") + "://127.0.0.1:" + std::to_string(port_) + "/" +
           path;
  }

  std::vector<AccessLine> accessLog() const {
    std::vector<AccessLine> lines;
    std::istringstream in(readWholeFile(dir_ / "access.log"));
    std::string text;
    while (std::getline(in, text)) {
      std::istringstream fields(text);
      AccessLine line;
      fields >> line.method >> line.path >> line.status >> line.bytes >> line.range >>
          line.protocol;
      lines.push_back(line);
    }
    return lines;
  }

  // The access log once it holds at least `lines` lines (or after 5 s, as it is): nginx writes
  // a request's line after sending the response, so a client can be done before its line is.
  std::vector<AccessLine> accessLogOf(std::size_t lines) const {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    std::vector<AccessLine> log = accessLog();
    while (log.size() < lines && std::chrono::steady_clock::now() < deadline) {
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
      log = accessLog();
    }
    return log;
  }

  // The access log once it holds a line for every request nginx has taken (or after 5 s, as it
  // is): for counts a test cannot know beforehand, read after its clients are done, whose last
  // lines may still be due. nginx counts the requests it takes (stub_status, served on a plain
  // port of its own whose requests are not logged); the log is settled when it holds a line for
  // each of them but the status requests themselves.
  std::vector<AccessLine> settledAccessLog() const {
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    for (;;) {
      const std::optional<std::uint64_t> taken = requestsTaken();
      std::vector<AccessLine> log = accessLog();
      if ((taken && log.size() + status_requests_ >= *taken) ||
          std::chrono::steady_clock::now() >= deadline) {
        return log;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
  }

 private:
  void writeConfig(const Options& o) {
    const std::string d = dir_.string();
    std::string listen = "listen 127.0.0.1:" + std::to_string(port_);
    std::string tls;
    if (tls_) {
      listen += " ssl http2";
      tls = "    ssl_certificate " + o.tls_certificate.string() + ";\n    ssl_certificate_key " +
            o.tls_key.string() + ";\n";
    }
    std::ofstream conf(dir_ / "nginx.conf");
    conf << "daemon off;\nmaster_process off;\nworker_processes 1;\n"
         << "pid " << d << "/nginx.pid;\nerror_log " << d << "/error.log warn;\n"
         << "events { worker_connections 256; }\n"
         << "http {\n"
         << "  log_format parallax '$request_method $uri $status $body_bytes_sent "
            "\"$http_range\" $server_protocol';\n"
         << "  access_log " << d << "/access.log parallax;\n"
         << "  client_body_temp_path " << d << "/client_body;\n"
         << "  proxy_temp_path " << d << "/proxy;\n"
         << "  fastcgi_temp_path " << d << "/fastcgi;\n"
         << "  uwsgi_temp_path " << d << "/uwsgi;\n"
         << "  scgi_temp_path " << d << "/scgi;\n"
         << "  default_type application/octet-stream;\n"
         << "  keepalive_requests 100000;\n"
         << "  server {\n    " << listen << ";\n"
         << tls << "    root " << o.root.string() << ";\n"
         << o.server_config << "\n  }\n"
         << "  server {\n    listen 127.0.0.1:" << status_port_ << ";\n"
         << "    access_log off;\n    location / { stub_status; }\n  }\n}\n";
  }

  // The requests nginx has taken so far, this one included (stub_status's third counter);
  // nothing when the status server does not answer.
  std::optional<std::uint64_t> requestsTaken() const {
    const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    address.sin_port = htons(std::uint16_t(status_port_));
    std::string reply;
    if (fd >= 0 && ::connect(fd, reinterpret_cast<sockaddr*>(&address), sizeof address) == 0) {
      const std::string request = "GET / HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n";
      if (::write(fd, request.data(), request.size()) == ssize_t(request.size())) {
        ++status_requests_;
        char buffer[1024];
        for (ssize_t got; (got = ::read(fd, buffer, sizeof buffer)) > 0;) reply.append(buffer, got);
      }
    }
    if (fd >= 0) ::close(fd);
    // "Active connections: 1 \nserver accepts handled requests\n 5 5 12 \nReading: ..."
    const auto at = reply.find("requests\n");
    if (at == std::string::npos) return std::nullopt;
    std::istringstream counters(reply.substr(at + 9));
    std::uint64_t accepts = 0, handled = 0, requests = 0;
    if (!(counters >> accepts >> handled >> requests)) return std::nullopt;
    return requests;
  }

  std::filesystem::path dir_;
  bool tls_ = false;
  int port_ = 0;
  int status_port_ = 0;
  mutable std::uint64_t status_requests_ = 0;
  ChildProcess process_;
};

// One line of the proxy's log.
struct ProxyLine {
  int index = 0;
  std::string path, range;
  int status = 0;
  std::string action;  // "pass" or the fault
};

class FaultProxy {
 public:
  // `args`: fault_proxy.py's options besides --upstream, --port and --log.
  FaultProxy(const std::filesystem::path& work_dir, int upstream_port,
             const std::vector<std::string>& args)
      : log_(work_dir / "proxy.log") {
    std::filesystem::create_directories(work_dir);
    // Debian's python3 first: a version manager's shim on PATH may cost a second a start.
    const std::string python = std::getenv("PARALLAX_PYTHON") ? std::getenv("PARALLAX_PYTHON")
                               : ::access("/usr/bin/python3", X_OK) == 0 ? "/usr/bin/python3"
                                                                         : "python3";
    std::vector<std::string> argv = {python,       PARALLAX_FAULT_PROXY,
                                     "--upstream", "127.0.0.1:" + std::to_string(upstream_port),
                                     "--log",      log_.string()};
    argv.insert(argv.end(), args.begin(), args.end());
    process_ = ChildProcess(python, argv, work_dir / "proxy_stderr.txt");
    const std::string line = process_.readLine(std::chrono::seconds(20));
    if (line.rfind("PORT ", 0) != 0) {
      throw std::runtime_error(
          "the fault proxy did not start (needs python3: Debian package "
          "'python3'): " +
          readWholeFile(work_dir / "proxy_stderr.txt"));
    }
    port_ = std::stoi(line.substr(5));
  }

  int port() const { return port_; }
  std::string url(const std::string& path) const {
    return "http://127.0.0.1:" + std::to_string(port_) + "/" + path;
  }
  std::vector<ProxyLine> log() const {
    std::vector<ProxyLine> lines;
    std::istringstream in(readWholeFile(log_));
    std::string text;
    while (std::getline(in, text)) {
      std::istringstream fields(text);
      ProxyLine line;
      fields >> line.index >> line.path >> line.range >> line.status >> line.action;
      lines.push_back(line);
    }
    return lines;
  }

 private:
  std::filesystem::path log_;
  ChildProcess process_;
  int port_ = 0;
};

}  // namespace parallax::test
