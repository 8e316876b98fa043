// A non-blocking UDP endpoint on 127.0.0.1 that carries actuator commands
// from an external controller to the simulator and sensor state back.
//
// Packet format, version 1. Every field is little-endian; one packet is one
// datagram.
//
//   offset  size  field
//   0       4     magic     the ASCII bytes "SDYN"
//   4       2     version   u16, 1
//   6       2     kind      u16, 1 = actuator command (controller -> simulator)
//                                2 = sensor state (simulator -> controller)
//   8       4     sequence  u32, set by the sender (the simulator counts its
//                           sensor packets from 0; commands are not reordered
//                           by it: the latest to arrive wins)
//   12      4     count     u32, number of f64 values after the header
//   16      8     time      f64, seconds of simulation time (sensor: the time
//                           of the state; command: informational)
//   24      8*count           f64 values
//
//   command payload: count = nv, the torque (or force) of each DOF in the
//                    model's DOF order; applied to regular DOFs, ignored for
//                    prescribed ones.
//   sensor payload:  count = nq + nv, q then v.
//
// Who may send (the security model; docs/guides/hil.md has the user's view):
//   - the socket is bound to 127.0.0.1, so only processes on this machine
//     reach it;
//   - commands are accepted from one sender only: 127.0.0.1 at the
//     configured command port, or (command port 0) the sender of the first
//     valid command, latched until release_peer(); datagrams from any other
//     address are counted in packets_rejected_sender and not parsed;
//   - sensor packets go to the configured destination port, else to the
//     accepted sender; another socket can neither command the simulator nor
//     take over its sensor stream.
//
// A datagram from the accepted sender whose size, magic, version, kind or
// count is wrong, or whose time or values are not all finite, is counted in
// packets_dropped and discarded. A command whose sequence number is not newer
// than the last accepted one (serial-number order, RFC 1982: newer means
// 1..2^31-1 ahead modulo 2^32) is counted in packets_stale and discarded; the
// first command after the peer is (re)latched sets the sequence.
//
// One poll() reads at most max_packets_per_poll datagrams (default 16), so a
// flood costs each step a bounded time; polls that leave datagrams waiting are
// counted (polls_left_pending). Datagrams the kernel discarded at this socket
// (receive buffer full) are read from the kernel's count (SO_MEMINFO, Linux;
// kernel_drops_counted() says whether it is available); datagrams lost before
// any socket (the per-CPU input backlog) are counted system-wide only, in
// /proc/net/softnet_stat. Sensor packets that the socket refused (sendto
// failed) are counted in send_failures.
//
// Memory and blocking policy: the socket and both packet buffers are created
// by the constructor (which throws std::runtime_error on failure, and
// std::invalid_argument when a sensor packet would not fit in one datagram);
// poll() and send_state() allocate nothing, never throw and never block.
#pragma once
#include <netinet/in.h>

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace soadyn {

namespace udp_packet {
constexpr char magic[4] = {'S', 'D', 'Y', 'N'};
constexpr std::uint16_t version = 1;
constexpr std::uint16_t kind_command = 1;
constexpr std::uint16_t kind_sensor = 2;
constexpr std::size_t header_bytes = 24;
constexpr std::size_t max_datagram_bytes = 65507;  // the largest UDP payload over IPv4
constexpr std::size_t bytes_for(std::size_t count) { return header_bytes + 8 * count; }
}  // namespace udp_packet

class UdpLink {
 public:
  // Binds 127.0.0.1:`port` (0: a free port chosen by the system, see port()).
  // `destination_port` > 0 sends every sensor packet to 127.0.0.1 at that
  // port; 0 replies to the accepted command sender. `command_port` > 0
  // accepts commands only from 127.0.0.1 at that port; 0 latches the sender
  // of the first valid command; -1 (the default) means `destination_port`
  // (a controller that sends from the socket it listens on). Throws
  // std::invalid_argument naming a port out of 0..65535.
  UdpLink(int nq, int nv, int port = 0, int destination_port = 0, int command_port = -1);
  ~UdpLink();
  UdpLink(const UdpLink&) = delete;
  UdpLink& operator=(const UdpLink&) = delete;

  int port() const { return port_; }
  int nq() const { return nq_; }
  int nv() const { return nv_; }

  // Setup: the most datagrams one poll() reads (>= 1; throws std::invalid_argument).
  void set_max_packets_per_poll(int n);
  int max_packets_per_poll() const { return max_packets_per_poll_; }
  // Thread-safe: forget the last sequence number (a restarted controller may
  // number from 0 again) and, without a fixed command port, the latched
  // sender: the next valid command's sender becomes the peer (sensor packets
  // go to the old peer until then).
  void release_peer() { release_requested_.store(true, std::memory_order_relaxed); }

  // Reads up to max_packets_per_poll pending datagrams. Returns true when at
  // least one valid command arrived; command() then holds the latest.
  bool poll();
  // The latest valid command's nv torques (zeros before the first one).
  const Eigen::VectorXd& command() const { return command_; }

  // Sends one sensor packet (time, q, v). Returns false when there is no
  // peer yet or the socket refused it (counted in send_failures).
  bool send_state(double time, const Eigen::VectorXd& q, const Eigen::VectorXd& v);

  // Counters, readable from any thread while the link is in use.
  std::uint64_t packets_received() const { return received_.load(std::memory_order_relaxed); }
  std::uint64_t packets_dropped() const { return dropped_.load(std::memory_order_relaxed); }
  std::uint64_t packets_sent() const { return sent_.load(std::memory_order_relaxed); }
  std::uint64_t packets_rejected_sender() const { return rejected_sender_.load(std::memory_order_relaxed); }
  std::uint64_t packets_stale() const { return stale_.load(std::memory_order_relaxed); }
  std::uint64_t kernel_drops() const;  // since the link was opened (a getsockopt call)
  bool kernel_drops_counted() const { return kernel_drops_counted_; }  // SO_MEMINFO available
  std::uint64_t send_failures() const { return send_failures_.load(std::memory_order_relaxed); }
  std::uint64_t polls_left_pending() const { return polls_left_pending_.load(std::memory_order_relaxed); }

 private:
  enum class Verdict { accepted, malformed, stale };
  // Reads one datagram into receive_buffer_; returns its size, or -1 when none is pending.
  long receive_one(sockaddr_in& sender);
  bool from_accepted_sender(const sockaddr_in& sender) const;
  // Validates the datagram in receive_buffer_ and copies its torques into
  // command_; leaves command_ alone for a malformed or stale one.
  Verdict accept_command(std::size_t size);
  bool datagram_pending();

  int nq_, nv_;
  int socket_ = -1;
  int port_ = 0;
  int max_packets_per_poll_ = 16;
  sockaddr_in peer_{};     // where sensor packets go
  sockaddr_in sender_{};   // whose commands are accepted
  bool has_peer_ = false, fixed_peer_ = false;
  bool has_sender_ = false, fixed_sender_ = false;
  bool has_sequence_ = false, kernel_drops_counted_ = false;
  std::uint32_t last_sequence_ = 0, send_sequence_ = 0;
  Eigen::VectorXd command_;
  // One byte larger than a command so that oversized datagrams are seen.
  std::vector<unsigned char> receive_buffer_, send_buffer_;
  std::atomic<bool> release_requested_{false};
  std::atomic<std::uint64_t> received_{0}, dropped_{0}, sent_{0}, rejected_sender_{0}, stale_{0}, send_failures_{0},
      polls_left_pending_{0};
};

}  // namespace soadyn
