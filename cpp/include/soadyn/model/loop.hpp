// Closed kinematic loops: a cut joint between a frame on one body (frame A)
// and a frame on another body or the world (frame B). The tree stays a tree;
// each loop adds closure equations Psi(q) = 0, their velocity form C v = 0
// and acceleration form C qdd = kappa ("Joint Coordinate Method, Part 1",
// Eqs. 1.6-1.8), whose Lagrange multipliers are the cut joint's reaction
// wrench (Saha, Shah & Nandihal 2013, Eqs. 50-54).
//
// Every equation is written in world-aligned axes. Its velocity row is one
// column w of a 6 x k matrix W (the loop's "constraint directions") applied
// to the relative spatial velocity [omega_A - omega_B; v_A - v_B(P)], where
// v_B(P) is the velocity of body B's point P (P = B's origin, or A's origin
// for "prismatic"). The multipliers lambda (k values) give the wrench
// [torque; force] that B's side exerts on A's side, about A's origin,
// world-aligned: W lambda. Kinds (residual, k, W):
//   point      p_A - p_B                                    3  [0; e_x], [0; e_y], [0; e_z]
//   revolute   p_A - p_B, x_A.(z_B x z_A), y_A.(z_B x z_A)  5  point's, [x_A; 0], [y_A; 0]
//   prismatic  log(R_A R_B'), x_B.(p_A - p_B), y_B.(...)    5  [e_i; 0] (3), [0; x_B], [0; y_B]  (P = p_A)
//   weld       log(R_A R_B'), p_A - p_B                     6  identity
//   distance   |p_A - p_B| - length                         1  [0; n], n = (p_A - p_B) / |p_A - p_B|
// (x_A, z_A: the axes of frame A in the world; log: the rotation vector.)
#pragma once
#include <stdexcept>
#include <string>
#include "soadyn/spatial/transform.hpp"

namespace soadyn {

enum class LoopKind { point, revolute, prismatic, weld, distance };

// Thrown by add_loop for a loop that cannot be built; the message names the loop.
struct LoopError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

// Number of closure equations of a kind.
inline int loop_equation_count(LoopKind kind) {
  switch (kind) {
    case LoopKind::point: return 3;
    case LoopKind::revolute: return 5;
    case LoopKind::prismatic: return 5;
    case LoopKind::weld: return 6;
    case LoopKind::distance: return 1;
  }
  return 0;
}

inline const char* loop_kind_name(LoopKind kind) {
  switch (kind) {
    case LoopKind::point: return "point";
    case LoopKind::revolute: return "revolute";
    case LoopKind::prismatic: return "prismatic";
    case LoopKind::weld: return "weld";
    case LoopKind::distance: return "distance";
  }
  return "unknown";
}

// The kind named `name`; throws LoopError naming the loop otherwise.
inline LoopKind parse_loop_kind(const std::string& name, const std::string& loop) {
  for (LoopKind k : {LoopKind::point, LoopKind::revolute, LoopKind::prismatic, LoopKind::weld, LoopKind::distance})
    if (name == loop_kind_name(k)) return k;
  throw LoopError("loop '" + loop + "': unknown kind '" + name +
                  "' (expected point, revolute, prismatic, weld or distance)");
}

// One loop as stored in the Model: both frames resolved to a body (-1: the
// world for B) and a placement in that body's frame.
template <class S>
struct LoopTpl {
  std::string name;
  LoopKind kind = LoopKind::point;
  int body_a = -1, body_b = -1;
  Transform<S> placement_a, placement_b;  // frame A in body_a's frame, frame B in body_b's frame (or the world)
  S length = S(0);                        // "distance" only
  int first_row = 0;                      // its first equation among the model's nloop_equations
  int rows() const { return loop_equation_count(kind); }
};

}  // namespace soadyn
