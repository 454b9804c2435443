#include "remote/server.h"

#include <chrono>
#include <thread>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <fmt/format.h>

#include "core/errors.h"
#include "model/robot.h"
#include "remote/openpi.h"
#include "remote/preset.h"
#include "remote/wire.h"

namespace hribench::remote {
namespace {

namespace asio = boost::asio;
namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
using tcp = asio::ip::tcp;

// The error text a Python server would send: a traceback whose last line names the error.
std::string traceback(const std::exception& e) {
  return fmt::format("Traceback (most recent call last):\n  hribench serve\n{}: {}\n",
                     dynamic_cast<const policy::PolicyError*>(&e) != nullptr ? "PolicyError" : "RuntimeError", e.what());
}

void handle_openpi_connection(tcp::socket socket, const PolicyMaker& make) {
  beast::error_code ec;
  beast::flat_buffer buffer;
  http::request<http::string_body> request;
  http::read(socket, buffer, request, ec);
  if (ec) return;
  if (!websocket::is_upgrade(request)) {
    const bool health = request.target() == "/healthz";
    http::response<http::string_body> response{health ? http::status::ok : http::status::upgrade_required,
                                               request.version()};
    response.set(http::field::content_type, "text/plain");
    response.body() = health ? "OK\n" : "Failed to open a WebSocket connection.\n";
    response.prepare_payload();
    http::write(socket, response, ec);
    socket.shutdown(tcp::socket::shutdown_send, ec);
    return;
  }
  websocket::stream<tcp::socket> ws(std::move(socket));
  ws.read_message_max(0);
  ws.accept(request, ec);
  if (ec) return;
  std::unique_ptr<policy::Policy> policy = make();
  ws.binary(true);
  ws.write(asio::buffer(pack(Map{{"hribench/spec", spec_to_value(policy->spec())}}, ArrayCodec::kOpenpi)), ec);
  if (ec) return;
  bool started = false;
  while (true) {
    beast::flat_buffer message;
    ws.read(message, ec);
    if (ec) return;  // the client went away
    try {
      const auto begin = std::chrono::steady_clock::now();
      const Value request_value = unpack(beast::buffers_to_string(message.data()));
      const policy::ActionChunk chunk = serve_query(*policy, openpi_groups(request_value.map("request")), started);
      const double infer_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - begin).count();
      Map reply;
      for (auto& [name, array] : encode_native_actions(chunk)) {
        reply.emplace_back(name, std::move(array));
      }
      reply.emplace_back("policy_timing", Map{{"infer_ms", infer_ms}});
      ws.binary(true);
      ws.write(asio::buffer(pack(reply, ArrayCodec::kOpenpi)), ec);
      if (ec) return;
    } catch (const std::exception& e) {
      ws.text(true);
      ws.write(asio::buffer(traceback(e)), ec);
      ws.close(websocket::close_reason(websocket::close_code::internal_error,
                                       "Internal server error. Traceback included in previous frame."),
               ec);
      return;
    }
  }
}

}  // namespace

policy::ActionChunk serve_query(policy::Policy& policy, const ObservationGroups& groups, bool& started) {
  const NativeQuery query = decode_native(groups, policy.spec());
  if (query.start) {
    policy.reset(*query.start);
    started = true;
  }
  if (!started) throw WireError("no episode started: an episode's first request carries the side channel's reset");
  policy::ActionChunk chunk = policy.act(query.observation);
  if (chunk.actions.empty()) throw policy::PolicyError(policy::PolicyErrorKind::kEmptyChunk, "the served policy returned no actions");
  return chunk;
}

void serve_openpi(const std::string& host, uint16_t port, const PolicyMaker& make,
                  const std::function<void(uint16_t)>& on_listening, const std::atomic<bool>& stop) {
  asio::io_context io;
  tcp::acceptor acceptor(io);
  beast::error_code ec;
  const tcp::endpoint endpoint(asio::ip::make_address(host, ec), port);
  if (ec) throw core::InputError("--host", "an IP address", "'" + host + "'");
  acceptor.open(endpoint.protocol(), ec);
  if (!ec) acceptor.set_option(asio::socket_base::reuse_address(true), ec);
  if (!ec) acceptor.bind(endpoint, ec);
  if (!ec) acceptor.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) throw core::InputError("--port", "a port free to listen on", fmt::format("{}: {}", port, ec.message()));
  acceptor.non_blocking(true);
  on_listening(acceptor.local_endpoint().port());
  while (!stop) {
    tcp::socket socket(io);
    acceptor.accept(socket, ec);
    if (ec == asio::error::would_block || ec == asio::error::try_again) {
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    if (ec) continue;
    socket.non_blocking(false);
    socket.set_option(tcp::no_delay(true), ec);
    std::thread([s = std::move(socket), make]() mutable { handle_openpi_connection(std::move(s), make); }).detach();
  }
}

}  // namespace hribench::remote
