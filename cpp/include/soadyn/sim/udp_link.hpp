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
// A received datagram whose size, magic, version, kind or count is wrong, or
// whose values are not all finite, is counted in packets_dropped and
// discarded. Sensor packets go to the configured destination port if one was
// given, else to the address the last valid command came from (none is sent
// before the first command arrives).
//
// Memory and blocking policy: the socket and both packet buffers are created
// by the constructor (which throws std::runtime_error on failure); poll() and
// send_state() allocate nothing, never throw and never block.
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
constexpr std::size_t bytes_for(std::size_t count) { return header_bytes + 8 * count; }
}  // namespace udp_packet

class UdpLink {
 public:
  // Binds 127.0.0.1:`port` (0: a free port chosen by the system, see port()).
  // `destination_port` > 0 sends every sensor packet to 127.0.0.1 at that
  // port; 0 replies to the sender of the last valid command.
  UdpLink(int nq, int nv, int port = 0, int destination_port = 0);
  ~UdpLink();
  UdpLink(const UdpLink&) = delete;
  UdpLink& operator=(const UdpLink&) = delete;

  int port() const { return port_; }
  int nq() const { return nq_; }
  int nv() const { return nv_; }

  // Drains every pending datagram. Returns true when at least one valid
  // command arrived; command() then holds the latest.
  bool poll();
  // The latest valid command's nv torques (zeros before the first one).
  const Eigen::VectorXd& command() const { return command_; }
  bool has_command() const { return has_command_; }

  // Sends one sensor packet (time, q, v). Returns false when there is no
  // peer yet or the socket would block (the packet is then not sent).
  bool send_state(double time, const Eigen::VectorXd& q, const Eigen::VectorXd& v);

  // Counters, readable from any thread while the link is in use.
  std::uint64_t packets_received() const { return received_.load(std::memory_order_relaxed); }
  std::uint64_t packets_dropped() const { return dropped_.load(std::memory_order_relaxed); }
  std::uint64_t packets_sent() const { return sent_.load(std::memory_order_relaxed); }

 private:
  // Validates the datagram in receive_buffer_ and copies its torques into
  // command_; returns false (leaving command_ alone) for a malformed one.
  bool accept_command(std::size_t size);

  int nq_, nv_;
  int socket_ = -1;
  int port_ = 0;
  sockaddr_in peer_{};
  bool has_peer_ = false, fixed_peer_ = false, has_command_ = false;
  std::uint32_t send_sequence_ = 0;
  Eigen::VectorXd command_;
  // One byte larger than a command so that oversized datagrams are seen.
  std::vector<unsigned char> receive_buffer_, send_buffer_;
  std::atomic<std::uint64_t> received_{0}, dropped_{0}, sent_{0};
};

}  // namespace soadyn
