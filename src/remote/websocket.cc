#include "remote/websocket.h"

#include <optional>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/steady_timer.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <fmt/format.h>

namespace hribench::remote {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;
using error_code = boost::system::error_code;

// Runs the asynchronous operation that start(on_done) begins on `io` until it completes or
// `timeout` passes; on timeout `socket` is closed (which completes the operation with an
// error) and the returned flag says so.
template <class Start>
bool run_with_deadline(asio::io_context& io, tcp::socket& socket, std::chrono::milliseconds timeout,
                       Start start) {
  io.restart();
  asio::steady_timer timer(io, timeout);
  bool timed_out = false;
  bool done = false;
  timer.async_wait([&](const error_code& ec) {
    if (!ec && !done) {
      timed_out = true;
      error_code ignored;
      socket.close(ignored);
    }
  });
  start([&] {
    done = true;
    timer.cancel();
  });
  io.run();
  return timed_out;
}

std::string describe(const error_code& ec) { return ec.message(); }

void connect(asio::io_context& io, tcp::socket& socket, const std::string& host, const std::string& port,
             std::chrono::milliseconds timeout) {
  tcp::resolver resolver(io);
  error_code ec;
  const auto endpoints = resolver.resolve(host, port, ec);
  if (ec) throw TransportError(fmt::format("cannot resolve {}: {}", host, describe(ec)), true);
  const bool timed_out = run_with_deadline(io, socket, timeout, [&](auto finish) {
    asio::async_connect(socket, endpoints, [&, finish](const error_code& e, const tcp::endpoint&) {
      ec = e;
      finish();
    });
  });
  if (timed_out) throw TransportError(fmt::format("{}:{}: no answer in {} ms", host, port, timeout.count()), true);
  if (ec) throw TransportError(fmt::format("{}:{}: {}", host, port, describe(ec)), true);
  socket.set_option(tcp::no_delay(true));
}

}  // namespace

int http_get(const std::string& host, const std::string& port, const std::string& path,
             std::chrono::milliseconds timeout, std::string& body) {
  asio::io_context io;
  tcp::socket socket(io);
  connect(io, socket, host, port, timeout);
  http::request<http::empty_body> request{http::verb::get, path, 11};
  request.set(http::field::host, host + ":" + port);
  request.set(http::field::user_agent, "hribench");
  request.set(http::field::connection, "close");
  beast::flat_buffer buffer;
  http::response<http::string_body> response;
  error_code ec;
  const bool timed_out = run_with_deadline(io, socket, timeout, [&](auto finish) {
    http::async_write(socket, request, [&, finish](const error_code& e, size_t) {
      if (e) {
        ec = e;
        finish();
        return;
      }
      http::async_read(socket, buffer, response, [&, finish](const error_code& e2, size_t) {
        ec = e2;
        finish();
      });
    });
  });
  if (timed_out) throw TransportError(fmt::format("GET {} on {}:{}: no answer in {} ms", path, host, port, timeout.count()), false);
  if (ec) throw TransportError(fmt::format("GET {} on {}:{}: {}", path, host, port, describe(ec)), false);
  body = response.body();
  return static_cast<int>(response.result_int());
}

struct WebSocketClient::Impl {
  asio::io_context io;
  websocket::stream<tcp::socket> ws{io};
  beast::flat_buffer buffer;
};

WebSocketClient::WebSocketClient(const std::string& host, const std::string& port,
                                 std::chrono::milliseconds timeout)
    : impl_(std::make_unique<Impl>()) {
  connect(impl_->io, impl_->ws.next_layer(), host, port, timeout);
  auto& ws = impl_->ws;
  ws.read_message_max(0);  // no limit, as the openpi server and client
  ws.auto_fragment(false);  // one frame per message, as openpi's client sends it
  websocket::stream_base::timeout options = websocket::stream_base::timeout::suggested(beast::role_type::client);
  options.keep_alive_pings = false;  // our deadlines bound every read instead
  options.idle_timeout = websocket::stream_base::none();
  options.handshake_timeout = websocket::stream_base::none();
  ws.set_option(options);
  ws.set_option(websocket::stream_base::decorator(
      [](websocket::request_type& req) { req.set(http::field::user_agent, "hribench"); }));
  ws.binary(true);
  error_code ec;
  const bool timed_out = run_with_deadline(impl_->io, ws.next_layer(), timeout, [&](auto finish) {
    ws.async_handshake(host + ":" + port, "/", [&, finish](const error_code& e) {
      ec = e;
      finish();
    });
  });
  if (timed_out) throw TransportError(fmt::format("no websocket upgrade from {}:{} in {} ms", host, port, timeout.count()), true);
  if (ec) throw TransportError(fmt::format("websocket upgrade refused by {}:{}: {}", host, port, describe(ec)), true);
}

WebSocketClient::~WebSocketClient() {
  error_code ignored;
  impl_->ws.next_layer().close(ignored);
}

void WebSocketClient::write_binary(const std::string& bytes, std::chrono::milliseconds timeout) {
  auto& ws = impl_->ws;
  error_code ec;
  const bool timed_out = run_with_deadline(impl_->io, ws.next_layer(), timeout, [&](auto finish) {
    ws.async_write(asio::buffer(bytes), [&, finish](const error_code& e, size_t) {
      ec = e;
      finish();
    });
  });
  if (timed_out) throw TransportError(fmt::format("sending took over {} ms", timeout.count()), false);
  if (ec) throw TransportError(fmt::format("sending failed: {}", describe(ec)), false);
}

WebSocketClient::Frame WebSocketClient::read(std::chrono::milliseconds timeout) {
  auto& ws = impl_->ws;
  impl_->buffer.clear();
  error_code ec;
  const bool timed_out = run_with_deadline(impl_->io, ws.next_layer(), timeout, [&](auto finish) {
    ws.async_read(impl_->buffer, [&, finish](const error_code& e, size_t) {
      ec = e;
      finish();
    });
  });
  if (timed_out) throw TransportError(fmt::format("no reply within {} ms", timeout.count()), false);
  if (ec == websocket::error::closed) {
    const websocket::close_reason& reason = ws.reason();
    throw TransportError(fmt::format("the server closed the connection (code {}{}{})", reason.code,
                                     reason.reason.empty() ? "" : ": ", std::string(reason.reason.c_str())),
                         false);
  }
  if (ec) throw TransportError(fmt::format("the connection broke: {}", describe(ec)), false);
  Frame frame;
  frame.text = ws.got_text();
  frame.data = beast::buffers_to_string(impl_->buffer.data());
  return frame;
}

int WebSocketClient::read_close(std::chrono::milliseconds timeout) {
  try {
    read(timeout);
  } catch (const TransportError&) {
  }
  return impl_->ws.reason().code;
}

}  // namespace hribench::remote
