// The UDP endpoint of the HIL runner; the packet format is in udp_link.hpp.
#include "soadyn/realtime/udp_link.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <sys/socket.h>
#include <unistd.h>
#ifdef __linux__
#include <linux/sock_diag.h>  // SK_MEMINFO_DROPS
#endif

#include <cerrno>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <string>

namespace soadyn {

namespace {

// Little-endian encoding, independent of the host's byte order.
void put_u16(unsigned char* p, std::uint16_t x) {
  p[0] = static_cast<unsigned char>(x);
  p[1] = static_cast<unsigned char>(x >> 8);
}

void put_u32(unsigned char* p, std::uint32_t x) {
  for (int k = 0; k < 4; ++k) p[k] = static_cast<unsigned char>(x >> (8 * k));
}

void put_f64(unsigned char* p, double x) {
  std::uint64_t bits;
  std::memcpy(&bits, &x, sizeof bits);
  for (int k = 0; k < 8; ++k) p[k] = static_cast<unsigned char>(bits >> (8 * k));
}

std::uint16_t get_u16(const unsigned char* p) { return static_cast<std::uint16_t>(p[0] | (p[1] << 8)); }

std::uint32_t get_u32(const unsigned char* p) {
  std::uint32_t x = 0;
  for (int k = 0; k < 4; ++k) x |= static_cast<std::uint32_t>(p[k]) << (8 * k);
  return x;
}

double get_f64(const unsigned char* p) {
  std::uint64_t bits = 0;
  for (int k = 0; k < 8; ++k) bits |= static_cast<std::uint64_t>(p[k]) << (8 * k);
  double x;
  std::memcpy(&x, &bits, sizeof x);
  return x;
}

sockaddr_in loopback_address(int port) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  address.sin_port = htons(static_cast<std::uint16_t>(port));
  address.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  return address;
}

// Closes the socket (if open) and throws with the current errno's message.
[[noreturn]] void fail(int socket, const std::string& what) {
  const int error = errno;
  if (socket >= 0) ::close(socket);
  throw std::runtime_error("UDP link: " + what + ": " + std::strerror(error));
}

void check_port(int port, const char* what) {
  if (port < 0 || port > 65535) throw std::invalid_argument(std::string(what) + " must be in 0..65535");
}

}  // namespace

UdpLink::UdpLink(int nq, int nv, int port, int destination_port, int command_port) : nq_(nq), nv_(nv) {
  if (nq < 0 || nv < 0) throw std::invalid_argument("UDP link: nq and nv must be >= 0");
  check_port(port, "UDP port");
  check_port(destination_port, "UDP destination port");
  if (command_port != -1) check_port(command_port, "UDP command port");
  const std::size_t sensor_bytes = udp_packet::bytes_for(static_cast<std::size_t>(nq) + static_cast<std::size_t>(nv));
  if (sensor_bytes > udp_packet::max_datagram_bytes)
    throw std::invalid_argument("UDP link: a sensor packet of nq + nv = " + std::to_string(nq + nv) +
                                " values does not fit in one datagram (at most " +
                                std::to_string((udp_packet::max_datagram_bytes - udp_packet::header_bytes) / 8) + ")");
  command_.setZero(nv);
  receive_buffer_.assign(udp_packet::bytes_for(static_cast<std::size_t>(nv)) + 1, 0);
  send_buffer_.assign(sensor_bytes, 0);

  socket_ = ::socket(AF_INET, SOCK_DGRAM, 0);
  if (socket_ < 0) fail(-1, "cannot open a socket");
  const int flags = ::fcntl(socket_, F_GETFL, 0);
  if (flags < 0 || ::fcntl(socket_, F_SETFL, flags | O_NONBLOCK) < 0)
    fail(socket_, "cannot make the socket non-blocking");
#ifdef SO_MEMINFO
  std::uint32_t info[SK_MEMINFO_VARS];
  socklen_t info_length = sizeof info;
  kernel_drops_counted_ = ::getsockopt(socket_, SOL_SOCKET, SO_MEMINFO, info, &info_length) == 0;
#endif
  sockaddr_in address = loopback_address(port);
  socklen_t length = sizeof address;
  if (::bind(socket_, reinterpret_cast<sockaddr*>(&address), length) < 0 ||
      ::getsockname(socket_, reinterpret_cast<sockaddr*>(&address), &length) < 0)
    fail(socket_, "cannot bind 127.0.0.1:" + std::to_string(port));
  port_ = ntohs(address.sin_port);
  if (destination_port > 0) {
    peer_ = loopback_address(destination_port);
    has_peer_ = fixed_peer_ = true;
  }
  if (command_port == -1) command_port = destination_port;
  if (command_port > 0) {
    sender_ = loopback_address(command_port);
    has_sender_ = fixed_sender_ = true;
  }
}

UdpLink::~UdpLink() {
  if (socket_ >= 0) ::close(socket_);
}

void UdpLink::set_max_packets_per_poll(int n) {
  if (n < 1) throw std::invalid_argument("UDP link: the packets read per step must be >= 1, got " + std::to_string(n));
  max_packets_per_poll_ = n;
}

bool UdpLink::poll() {
  if (release_requested_.exchange(false, std::memory_order_relaxed)) {  // a restarted controller may number from 0
    has_sequence_ = false;
    if (!fixed_sender_) has_sender_ = false;
  }
  bool got_command = false;
  for (int read = 0; read < max_packets_per_poll_; ++read) {
    sockaddr_in sender{};
    const long size = receive_one(sender);
    if (size < 0) return got_command;
    if (has_sender_ && !from_accepted_sender(sender)) {
      rejected_sender_.fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    const Verdict verdict = accept_command(static_cast<std::size_t>(size));
    if (verdict != Verdict::accepted) {
      (verdict == Verdict::stale ? stale_ : dropped_).fetch_add(1, std::memory_order_relaxed);
      continue;
    }
    received_.fetch_add(1, std::memory_order_relaxed);
    got_command = true;
    if (!has_sender_) {  // latch the first valid sender
      sender_ = sender;
      has_sender_ = true;
    }
    if (!fixed_peer_) {
      peer_ = sender_;
      has_peer_ = true;
    }
  }
  if (datagram_pending()) polls_left_pending_.fetch_add(1, std::memory_order_relaxed);
  return got_command;
}

long UdpLink::receive_one(sockaddr_in& sender) {
  for (;;) {
    socklen_t sender_length = sizeof sender;
    const ssize_t size = ::recvfrom(socket_, receive_buffer_.data(), receive_buffer_.size(), MSG_DONTWAIT,
                                    reinterpret_cast<sockaddr*>(&sender), &sender_length);
    // ECONNREFUSED reports (once) that an earlier sensor packet found no
    // listener; keep reading. EAGAIN means drained; on any other error try
    // again at the next step.
    if (size < 0 && (errno == EINTR || errno == ECONNREFUSED)) continue;
    return size < 0 ? -1 : static_cast<long>(size);
  }
}

std::uint64_t UdpLink::kernel_drops() const {
#ifdef SO_MEMINFO
  // The socket's drop count now (SK_MEMINFO_DROPS). SO_RXQ_OVFL would stamp
  // each datagram with the count at the time it was queued, and so miss the
  // drops after the last datagram read.
  std::uint32_t info[SK_MEMINFO_VARS] = {};
  socklen_t length = sizeof info;
  if (::getsockopt(socket_, SOL_SOCKET, SO_MEMINFO, info, &length) == 0 && length > SK_MEMINFO_DROPS * sizeof info[0])
    return info[SK_MEMINFO_DROPS];
#endif
  return 0;
}

bool UdpLink::datagram_pending() {
  unsigned char byte;
  return ::recv(socket_, &byte, 1, MSG_DONTWAIT | MSG_PEEK) >= 0;
}

bool UdpLink::from_accepted_sender(const sockaddr_in& sender) const {
  return sender.sin_family == sender_.sin_family && sender.sin_addr.s_addr == sender_.sin_addr.s_addr &&
         sender.sin_port == sender_.sin_port;
}

UdpLink::Verdict UdpLink::accept_command(std::size_t size) {
  const unsigned char* p = receive_buffer_.data();
  const std::size_t count = static_cast<std::size_t>(nv_);
  if (size != udp_packet::bytes_for(count) || std::memcmp(p, udp_packet::magic, 4) != 0 ||
      get_u16(p + 4) != udp_packet::version || get_u16(p + 6) != udp_packet::kind_command ||
      get_u32(p + 12) != count || !std::isfinite(get_f64(p + 16)))
    return Verdict::malformed;
  const unsigned char* values = p + udp_packet::header_bytes;
  for (std::size_t k = 0; k < count; ++k)
    if (!std::isfinite(get_f64(values + 8 * k))) return Verdict::malformed;
  const std::uint32_t sequence = get_u32(p + 8);
  // Serial-number order (RFC 1982): newer when 1..2^31-1 ahead, modulo 2^32.
  if (has_sequence_ && static_cast<std::int32_t>(sequence - last_sequence_) <= 0) return Verdict::stale;
  last_sequence_ = sequence;
  has_sequence_ = true;
  for (std::size_t k = 0; k < count; ++k) command_[static_cast<Eigen::Index>(k)] = get_f64(values + 8 * k);
  return Verdict::accepted;
}

bool UdpLink::send_state(double time, const Eigen::VectorXd& q, const Eigen::VectorXd& v) {
  if (!has_peer_ || q.size() != nq_ || v.size() != nv_) return false;
  unsigned char* p = send_buffer_.data();
  std::memcpy(p, udp_packet::magic, 4);
  put_u16(p + 4, udp_packet::version);
  put_u16(p + 6, udp_packet::kind_sensor);
  put_u32(p + 8, send_sequence_);
  put_u32(p + 12, static_cast<std::uint32_t>(nq_ + nv_));
  put_f64(p + 16, time);
  unsigned char* values = p + udp_packet::header_bytes;
  for (int k = 0; k < nq_; ++k) put_f64(values + 8 * k, q[k]);
  for (int k = 0; k < nv_; ++k) put_f64(values + 8 * (nq_ + k), v[k]);
  ssize_t sent;
  do {
    sent = ::sendto(socket_, p, send_buffer_.size(), MSG_DONTWAIT, reinterpret_cast<const sockaddr*>(&peer_),
                    sizeof peer_);
  } while (sent < 0 && errno == EINTR);
  if (sent != static_cast<ssize_t>(send_buffer_.size())) {
    send_failures_.fetch_add(1, std::memory_order_relaxed);
    return false;
  }
  ++send_sequence_;
  sent_.fetch_add(1, std::memory_order_relaxed);
  return true;
}

}  // namespace soadyn
