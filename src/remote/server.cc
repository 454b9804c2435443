#include "remote/server.h"

#include <chrono>
#include <iterator>
#include <map>
#include <memory>
#include <thread>

#include <zmq.hpp>
#include <zmq_addon.hpp>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>
#include <fmt/format.h>

#include "core/errors.h"
#include "model/robot.h"
#include "remote/gr00t.h"
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
  ws.auto_fragment(false);  // one frame per message
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
      for (auto& [name, array] : encode_native_actions(chunk, false)) {
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

void serve_gr00t(const std::string& host, uint16_t port, const PolicyMaker& make,
                 const std::function<void(uint16_t)>& on_listening, const std::atomic<bool>& stop) {
  zmq::context_t context(1);
  // A ROUTER socket: it answers REQ clients as a REP socket does, and tells them apart by the
  // routing frame it receives before each request (identity, empty delimiter, request).
  zmq::socket_t router(context, zmq::socket_type::router);
  router.set(zmq::sockopt::linger, 0);
  try {
    router.bind(fmt::format("tcp://{}:{}", host, port == 0 ? std::string("*") : std::to_string(port)));
  } catch (const zmq::error_t& e) {
    throw core::InputError("--port", "a port free to listen on", fmt::format("{}: {}", port, e.what()));
  }
  const std::string bound = router.get(zmq::sockopt::last_endpoint);
  on_listening(static_cast<uint16_t>(std::stoi(bound.substr(bound.rfind(':') + 1))));
  struct Session {
    std::unique_ptr<policy::Policy> policy;
    bool started = false;
  };
  std::map<std::string, Session> sessions;  // by the client socket's routing identity
  const std::unique_ptr<policy::Policy> spec_source = make();
  while (!stop) {
    zmq::pollitem_t items[] = {{router.handle(), 0, ZMQ_POLLIN, 0}};
    zmq::poll(items, 1, std::chrono::milliseconds(100));
    if ((items[0].revents & ZMQ_POLLIN) == 0) continue;
    std::vector<zmq::message_t> frames;
    if (!zmq::recv_multipart(router, std::back_inserter(frames))) continue;
    if (frames.size() != 3 || frames[1].size() != 0) continue;  // not a REQ client's request
    const std::string client = frames[0].to_string();
    const zmq::message_t& message = frames[2];
    Value reply;
    bool kill = false;
    try {
      const Value request = unpack(std::string_view(static_cast<const char*>(message.data()), message.size()));
      const Map& envelope = request.map("request");
      const Value* endpoint_value = find(envelope, "endpoint");
      const std::string endpoint = endpoint_value != nullptr ? endpoint_value->str("endpoint") : "get_action";
      if (endpoint == "ping") {
        reply = Map{{"status", "ok"}, {"message", "Server is running"}};
      } else if (endpoint == "kill") {
        kill = true;
      } else if (endpoint == "get_modality_config") {
        reply = Map{{"hribench/spec", spec_to_value(spec_source->spec())}};
      } else if (endpoint == "reset") {
        sessions[client].started = false;
        reply = Map{};
      } else if (endpoint == "get_action") {
        const Map& data = at(envelope, "data", "request").map("data");
        const Gr00tEra era = find(data, "observation") != nullptr ? Gr00tEra::kN16 : Gr00tEra::kN15;
        Session& session = sessions[client];
        if (!session.policy) session.policy = make();
        reply = gr00t_reply(encode_native_actions(serve_query(*session.policy, gr00t_groups(data), session.started), true),
                            era);
      } else {
        reply = Map{{"error", "Unknown endpoint: " + endpoint}};
      }
    } catch (const std::exception& e) {
      reply = Map{{"error", std::string(dynamic_cast<const policy::PolicyError*>(&e) != nullptr ? "PolicyError: " : "") + e.what()}};
    }
    const std::string bytes = pack(reply, ArrayCodec::kGr00t);
    router.send(frames[0], zmq::send_flags::sndmore);
    router.send(zmq::message_t(), zmq::send_flags::sndmore);
    router.send(zmq::buffer(bytes), zmq::send_flags::none);
    if (kill) return;
  }
}

}  // namespace hribench::remote
