#pragma once
// A blocking websocket client with a deadline on every operation (Boost.Beast), as the openpi
// client needs it (docs/remote-policies.md): no permessage-deflate, no message size limit, no
// keep-alive pings (the openpi server cannot answer pings while it infers), binary frames out,
// binary or text frames in. Every call that exceeds its deadline closes the socket and throws
// TransportError; so does any network failure. Plus an HTTP GET for the health check.

#include <chrono>
#include <memory>
#include <stdexcept>
#include <string>

namespace hribench::remote {

// The connection failed (refused, reset, closed, timed out).
class TransportError : public std::runtime_error {
 public:
  TransportError(const std::string& message, bool connect_failure)
      : std::runtime_error(message), connect_failure_(connect_failure) {}
  // True when no connection could be made (nothing listens, the handshake failed).
  bool connect_failure() const { return connect_failure_; }

 private:
  bool connect_failure_;
};

// `GET path` on host:port; returns the status code and fills `body`. Throws TransportError.
int http_get(const std::string& host, const std::string& port, const std::string& path,
             std::chrono::milliseconds timeout, std::string& body);

class WebSocketClient {
 public:
  // Connects and completes the websocket upgrade of ws://host:port/ within `timeout`.
  WebSocketClient(const std::string& host, const std::string& port, std::chrono::milliseconds timeout);
  ~WebSocketClient();
  WebSocketClient(const WebSocketClient&) = delete;
  WebSocketClient& operator=(const WebSocketClient&) = delete;

  struct Frame {
    std::string data;
    bool text = false;
  };
  void write_binary(const std::string& bytes, std::chrono::milliseconds timeout);
  // The next message. A close from the server throws TransportError naming its code and reason.
  Frame read(std::chrono::milliseconds timeout);
  // After a text frame (openpi's error): waits up to `timeout` for the server's close and
  // returns its code (0 if none came).
  int read_close(std::chrono::milliseconds timeout);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hribench::remote
