// The joint-angle table the tree-frame sweeps read (soadyn/algorithms/
// joint_angles.hpp) against the C library's std::sin and std::cos: a chain
// of axis-aligned revolute joints about +-x, +-y and +-z, with joints of
// other kinds between them (universal joints about coordinate axes take two
// slots, the others none), at angles from 1e-300 to 1e22, random angles,
// exact multiples of pi/2, and non-finite angles.
// - every axis-aligned revolute joint has a slot, every universal joint
//   about coordinate axes two, every other joint none;
// - the table's angle is the coordinate times the axis' sign, exactly;
// - its sine and cosine are within 4 units in the last place of 1 of the
//   C library's (the vector library's documented bound), in double and float,
//   for the kernel the sweeps use and for every other kernel this processor
//   can run;
// - an infinite or NaN angle gives NaN, never a crash or a finite value;
// - eight threads making the process's first calls at once get the same
//   tables as one thread.
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "failure_count.hpp"
#include "random_tree.hpp"
#include "threads_at_once.hpp"
#include "soadyn/sweeps/joint_angles.hpp"
#include "soadyn/model/model_cast.hxx"  // ModelTpl::cast
#include "soadyn/soadyn.hpp"

namespace {

using soadyn_test::check;
using soadyn_test::failures;

// 48 bodies in a chain: every fourth a prismatic, spherical, any-axis
// revolute, universal about -e_k and e_k+1, or universal with one axis off
// the coordinate axes; the rest revolute about +-e_k.
soadyn::Model chain_model() {
  soadyn::Model m;
  soadyn_test::Random rng(7);
  std::string parent = "world";
  for (int b = 0; b < 48; ++b) {
    const double sign = (b / 3) % 2 == 0 ? 1.0 : -1.0;
    const soadyn::Vec3<double> axis = sign * soadyn::Vec3<double>::Unit(b % 3);
    soadyn::JointModel<double> joint = soadyn::RevoluteJoint<double>{axis};
    if (b % 4 == 3) {
      const soadyn::Vec3<double> next_axis = soadyn::Vec3<double>::Unit((b + 1) % 3);
      switch ((b / 4) % 5) {
        case 0: joint = soadyn::PrismaticJoint<double>{axis}; break;
        case 1: joint = soadyn::SphericalJoint<double>{}; break;
        case 2: joint = soadyn::RevoluteJoint<double>{rng.unit_vector()}; break;
        case 3: joint = soadyn::UniversalJoint<double>{-axis, next_axis}; break;
        default: joint = soadyn::UniversalJoint<double>{axis, soadyn::Vec3<double>(next_axis + 0.5 * axis)}; break;
      }
    }
    soadyn::Transform<double> placement;
    placement.rotation = rng.rotation();
    placement.translation = rng.uniform_vector3(0.3);
    const std::string name = "link" + std::to_string(b);
    m.add_body(name, parent, joint, placement, 1.0, rng.uniform_vector3(0.1), rng.box_inertia(1.0, 0.1, 0.3));
    parent = name;
  }
  return m;
}

// Angles for the slots, cycled: tiny to huge, random, and multiples of pi/2.
std::vector<double> test_angles(soadyn_test::Random& rng, int count) {
  std::vector<double> a = {0.0,     -0.0,    1e-300, -1e-300, 1e-8,  std::acos(-1.0) / 2, std::acos(-1.0),
                           -std::acos(-1.0), 3 * std::acos(-1.0) / 2, 1e3,  -1e5,  123456.789, 1e8,
                           -1e15,   1e22,    -1e22,  std::numeric_limits<double>::max()};
  while (static_cast<int>(a.size()) < count) a.push_back(rng.uniform(-20.0, 20.0));
  return a;
}

template <class S>
double ulp_error_of_one(S value, S reference) {
  return std::abs(static_cast<double>(value) - static_cast<double>(reference)) /
         static_cast<double>(std::numeric_limits<S>::epsilon());
}

// Sets q from `angles` (one per slot, cycled from `first`), tabulates, and
// compares. Returns the largest error in units of epsilon.
template <class S>
double compare(const soadyn::ModelTpl<S>& m, soadyn::DataTpl<S>& d, const std::vector<double>& angles,
               std::size_t first, int& compared) {
  Eigen::Matrix<S, Eigen::Dynamic, 1> q(m.nq);
  soadyn::neutral_configuration<S>(m, q);
  const std::size_t slots = m.angle_coordinates.size();
  for (std::size_t k = 0; k < slots; ++k) q[m.angle_coordinates[k]] = static_cast<S>(angles[(first + k) % angles.size()]);
  soadyn::tabulate_joint_angles(m, d.sweep, q.data());
  double worst = 0;
  for (std::size_t k = 0; k < slots; ++k) {
    const Eigen::Index slot = static_cast<Eigen::Index>(k);
    const S angle = q[m.angle_coordinates[k]] * m.angle_signs[k];
    const S table_angle = d.sweep.tree_joint_angle[slot];
    check(table_angle == angle || (std::isnan(table_angle) && std::isnan(angle)),
          "slot " + std::to_string(k) + ": the angle is not sign times coordinate");
    const double e = std::max(ulp_error_of_one(d.sweep.tree_joint_sine[slot], S(std::sin(angle))),
                              ulp_error_of_one(d.sweep.tree_joint_cosine[slot], S(std::cos(angle))));
    check(e <= 4.0, "slot " + std::to_string(k) + ": angle " + std::to_string(static_cast<double>(angle)) + " off by " +
                        std::to_string(e) + " ulp");
    worst = std::max(worst, e);
    ++compared;
  }
  return worst;
}

// Infinite and NaN angles in every slot: the table holds NaN.
template <class S>
int non_finite(const soadyn::ModelTpl<S>& m, soadyn::DataTpl<S>& d) {
  int nan_entries = 0;
  for (const S bad : {std::numeric_limits<S>::infinity(), -std::numeric_limits<S>::infinity(),
                      std::numeric_limits<S>::quiet_NaN()}) {
    Eigen::Matrix<S, Eigen::Dynamic, 1> q(m.nq);
  soadyn::neutral_configuration<S>(m, q);
    for (const int coordinate : m.angle_coordinates) q[coordinate] = bad;
    soadyn::tabulate_joint_angles(m, d.sweep, q.data());
    for (std::size_t k = 0; k < m.angle_coordinates.size(); ++k) {
      const Eigen::Index slot = static_cast<Eigen::Index>(k);
      const bool nan = std::isnan(d.sweep.tree_joint_sine[slot]) && std::isnan(d.sweep.tree_joint_cosine[slot]);
      check(nan, "slot " + std::to_string(k) + ": a non-finite angle gave a number");
      nan_entries += nan ? 1 : 0;
    }
  }
  return nan_entries;
}

// Every kernel this processor can run, on the raw angles and on non-finite
// ones; returns "name (max error)" for each.
std::string compare_kernels(std::vector<double> angles) {
  for (const double bad : {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                           std::numeric_limits<double>::quiet_NaN()})
    angles.push_back(bad);
  angles.push_back(0.5);  // a count that is not a multiple of four: the last vector's spare lanes
  // Slot k reads coordinate k with sign +1 (odd slots) or -1 (even slots, from negated coordinates).
  std::vector<int> coordinate_index(angles.size());
  std::vector<double> coordinate(angles.size()), sign(angles.size());
  for (std::size_t k = 0; k < angles.size(); ++k) {
    coordinate_index[k] = static_cast<int>(k);
    sign[k] = k % 2 == 0 ? -1.0 : 1.0;
    coordinate[k] = sign[k] * angles[k];
  }
  const soadyn::JointAngleSources<double> sources{coordinate.data(), coordinate_index.data(), sign.data(),
                                                  static_cast<Eigen::Index>(angles.size())};
  const std::size_t padded = (angles.size() + 3) / 4 * 4;
  std::string summary;
  for (const soadyn::detail::SineCosineKernel& kernel : soadyn::detail::available_sine_cosine_kernels()) {
    std::vector<double> angle(padded, -7.0), sine(padded, -7.0), cosine(padded, -7.0);
    kernel.run(sources, angle.data(), sine.data(), cosine.data());
    double worst = 0;
    for (std::size_t k = 0; k < angles.size(); ++k) {
      check(angle[k] == angles[k] || (std::isnan(angle[k]) && std::isnan(angles[k])),
            std::string(kernel.name) + ": slot " + std::to_string(k) + "'s angle is not sign times coordinate");
      const std::string at = std::string(kernel.name) + ", angle " + std::to_string(angles[k]);
      if (!std::isfinite(angles[k])) {
        check(std::isnan(sine[k]) && std::isnan(cosine[k]), at + ": a number for a non-finite angle");
        continue;
      }
      const double e = std::max(ulp_error_of_one(sine[k], std::sin(angles[k])),
                                ulp_error_of_one(cosine[k], std::cos(angles[k])));
      check(e <= 4.0, at + ": off by " + std::to_string(e) + " ulp");
      worst = std::max(worst, e);
    }
    char line[96];
    std::snprintf(line, sizeof line, "%s%s (%.2f ulp)", summary.empty() ? "" : ", ", kernel.name, worst);
    summary += line;
  }
  return summary;
}

// Eight threads make the process's first tabulations at once (the kernel is
// chosen by whichever gets there first), each on its own Data, 1000 times;
// every table must equal the one a single thread makes afterwards. Returns
// the number of tables that differ.
int first_calls_from_threads(const soadyn::Model& m, const std::vector<double>& angles) {
  constexpr int kThreads = 8, kCalls = 1000;
  Eigen::VectorXd q(m.nq);
  soadyn::neutral_configuration<double>(m, q);
  for (std::size_t k = 0; k < m.angle_coordinates.size(); ++k) q[m.angle_coordinates[k]] = angles[k % angles.size()];
  std::vector<soadyn::Data> data(kThreads, soadyn::Data(m));
  soadyn_test::calls_from_threads_at_once(kThreads, kCalls, [&](int t) {
    soadyn::tabulate_joint_angles(m, data[static_cast<std::size_t>(t)].sweep, q.data());
    return true;
  });
  soadyn::Data reference(m);
  soadyn::tabulate_joint_angles(m, reference.sweep, q.data());
  int differing = 0;
  for (const soadyn::Data& d : data)
    differing += d.sweep.tree_joint_sine != reference.sweep.tree_joint_sine ||
                 d.sweep.tree_joint_cosine != reference.sweep.tree_joint_cosine;
  check(differing == 0, "a thread's table differs from the single-thread table");
  return differing;
}

}  // namespace

int main() {
  const soadyn::Model m = chain_model();
  {
    soadyn_test::Random rng(5);
    const int differing = first_calls_from_threads(m, test_angles(rng, 64));
    std::printf("threads: 8 threads from the process's first call, 1000 tables each, %d differ\n", differing);
  }
  int aligned = 0, aligned_universal = 0;
  for (int b = 0; b < m.nbodies(); ++b) {
    const std::size_t i = static_cast<std::size_t>(b);
    const soadyn::JointFastPath k = m.joint_fast_path[i];
    const bool revolute_aligned = soadyn::joint_turning_axis(k) >= 0;
    const auto* universal = std::get_if<soadyn::UniversalJoint<double>>(&m.joints[i]);
    double sign1 = 0, sign2 = 0;
    const bool universal_aligned = universal && soadyn::coordinate_axis(universal->axis1, sign1) >= 0 &&
                                   soadyn::coordinate_axis(universal->axis2, sign2) >= 0;
    const int slot = m.angle_slot[i];
    const std::size_t s = static_cast<std::size_t>(slot);
    const bool right = revolute_aligned    ? slot >= 0 && m.angle_coordinates[s] == m.q_index[i] &&
                                              m.angle_signs[s] == m.axis_sign[i]
                       : universal_aligned ? slot >= 0 && m.angle_coordinates[s] == m.q_index[i] &&
                                                 m.angle_coordinates[s + 1] == m.q_index[i] + 1 &&
                                                 m.angle_signs[s] == sign1 && m.angle_signs[s + 1] == sign2
                                           : slot == -1;
    check(right, "body " + std::to_string(b) + ": wrong slot");
    aligned += revolute_aligned ? 1 : 0;
    aligned_universal += universal_aligned ? 1 : 0;
  }
  check(aligned == 36 && aligned_universal == 2 && static_cast<int>(m.angle_coordinates.size()) == 40,
        "36 axis-aligned revolute joints and 2 universal joints about coordinate axes");
  std::printf("model: %d bodies, %zu table slots, kernel %s\n", m.nbodies(), m.angle_coordinates.size(),
              soadyn::joint_angle_kernel());

  soadyn_test::Random rng(11);
  const std::vector<double> angles = test_angles(rng, 2000);
  soadyn::Data d(m);
  int compared = 0;
  double worst = 0;
  for (std::size_t first = 0; first < angles.size(); first += m.angle_coordinates.size())
    worst = std::max(worst, compare(m, d, angles, first, compared));
  const int nan_entries = non_finite(m, d);
  // The kernels also on angles where the reduction by pi/2 is hardest (the
  // neighbours of multiples of pi/2 up to 2^20 of them) and across the
  // polynomial kernel's reach (1e9) and beyond it.
  std::vector<double> kernel_angles = angles;
  for (double multiple = 1; multiple < 1 << 20; multiple *= 3) {
    const double near = multiple * std::acos(-1.0) / 2;
    for (const double a : {near, std::nextafter(near, 0.0), std::nextafter(near, 1e300), -near})
      kernel_angles.push_back(a);
  }
  for (int k = 0; k < 400; ++k) kernel_angles.push_back(rng.uniform(-1.2e9, 1.2e9));
  std::printf("kernels: %s\n", compare_kernels(kernel_angles).c_str());

  const soadyn::ModelTpl<float> mf = m.cast<float>();
  soadyn::DataTpl<float> df(mf);
  std::vector<double> float_angles;
  for (const double a : angles)
    if (std::abs(a) < 1e30) float_angles.push_back(a);
  int compared_float = 0;
  double worst_float = 0;
  for (std::size_t first = 0; first < float_angles.size(); first += mf.angle_coordinates.size())
    worst_float = std::max(worst_float, compare(mf, df, float_angles, first, compared_float));
  const int nan_entries_float = non_finite(mf, df);

  std::printf("double: %d angles, max error %.2f ulp; float: %d angles, max error %.2f ulp (tolerance 4 ulp)\n",
              compared, worst, compared_float, worst_float);
  std::printf("non-finite angles: %d of %d double entries NaN, %d of %d float\n", nan_entries,
              3 * static_cast<int>(m.angle_coordinates.size()), nan_entries_float,
              3 * static_cast<int>(mf.angle_coordinates.size()));
  if (failures == 0) std::printf("test_joint_angles: PASS\n");
  return failures == 0 ? 0 : 1;
}
