// Model files (soadyn/model/model_file.hpp) from C++: every model the library can
// build is saved, loaded and saved again, and
// - the second text equals the first (nothing lost, numbers exact);
// - the loaded model's dynamics equal the original's bit for bit at random
//   states (hybrid dynamics with its prescribed/regular mask, or
//   constrained dynamics for the loop scenes);
// and hostile texts (truncated, wrong types, non-finite numbers, unknown
// keys, a newer version, unknown parents) each give a ModelFileError naming
// the item at fault, never a crash.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "failure_count.hpp"
#include "random_tree.hpp"
#include "soadyn/soadyn.hpp"
#include "soadyn_scenes/scenes.hpp"

namespace {

using soadyn_test::check;
using soadyn_test::failures;

// Bit-identical dynamics of two models at 5 random states.
bool same_dynamics(const soadyn::Model& a, const soadyn::Model& b) {
  soadyn::Data da(a), db(b);
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const soadyn_test::State s = soadyn_test::random_state(a, seed);
    const bool loops = a.nloops() > 0;
    const soadyn::Status sa = loops ? soadyn::constrained_dynamics<double>(a, da, s.q, s.v, s.u)
                                    : soadyn::hybrid_dynamics<double>(a, da, s.q, s.v, s.u, s.f_ext.data());
    const soadyn::Status sb = loops ? soadyn::constrained_dynamics<double>(b, db, s.q, s.v, s.u)
                                    : soadyn::hybrid_dynamics<double>(b, db, s.q, s.v, s.u, s.f_ext.data());
    if (sa.ok() != sb.ok() || !(da.qdd.array() == db.qdd.array()).all() || !(da.tau.array() == db.tau.array()).all())
      return false;
  }
  return true;
}

int round_trips = 0;

void round_trip(const std::string& label, const soadyn::Model& model) {
  const std::string text = soadyn::model_to_json(model);
  const soadyn::Model loaded = soadyn::model_from_json(text, label);
  const std::string again = soadyn::model_to_json(loaded);
  if (again != text) {
    std::size_t at = 0;
    while (at < text.size() && at < again.size() && text[at] == again[at]) ++at;
    const std::size_t from = at > 200 ? at - 200 : 0;
    check(false, label + ": the saved text of the loaded model differs at character " + std::to_string(at) + ":\n" +
                     text.substr(from, 300) + "\n---- loaded:\n" + again.substr(from, 300));
  }
  check(loaded.nq == model.nq && loaded.nv == model.nv && loaded.nbodies() == model.nbodies() &&
            loaded.nloops() == model.nloops() && loaded.frames.size() == model.frames.size(),
        label + ": sizes differ");
  check(same_dynamics(model, loaded), label + ": dynamics differ");
  ++round_trips;
}

int refused = 0;

// `text` must be refused with a ModelFileError whose message contains `names`.
void refuse(const std::string& text, const std::string& names) {
  try {
    (void)soadyn::model_from_json(text, "hostile");
    check(false, "accepted a hostile text (expected an error naming '" + names + "')");
  } catch (const soadyn::ModelFileError& e) {
    check(std::string(e.what()).find(names) != std::string::npos,
          "error '" + std::string(e.what()) + "' does not name '" + names + "'");
    ++refused;
  } catch (const std::exception& e) {
    check(false, std::string("a hostile text raised another exception: ") + e.what());
  }
}

std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  if (at == std::string::npos) {
    check(false, "the test's text lacks '" + from + "'");
    return text;
  }
  return text.replace(at, from.size(), to);
}

}  // namespace

int main() {
  round_trip("cassini", soadyn::cassini_model<double>());
  round_trip("four_bar", soadyn::four_bar_model<double>());
  round_trip("slider_crank", soadyn::slider_crank_model<double>());
  round_trip("delta_robot", soadyn::delta_robot_model<double>());
  for (std::uint64_t seed = 1; seed <= 10; ++seed) {
    soadyn::Model model = soadyn_test::build_model<double>(soadyn_test::random_tree_spec(seed, 12));
    if (seed % 2 == 0) soadyn_test::add_flexible_bodies(model);
    soadyn_test::Random rng(seed);
    soadyn_test::apply_mask(model, soadyn_test::random_mask(model.nv, rng, 0.3));
    model.set_armature(0, 0.25 + 0.01 * static_cast<double>(seed));
    bool spring_added = false;  // on the last DOF with a scalar coordinate
    for (int dof = model.nv - 1; dof >= 0 && !spring_added; --dof) try {
        model.add_joint_spring("spring", dof, 3.0, 0.2, 0.1);
        spring_added = true;
      } catch (const std::invalid_argument&) {
      }
    check(spring_added, "a joint spring on random tree " + std::to_string(seed));
    model.add_point_spring("strut", model.body_names[1], "world", soadyn::Vec3<double>(0.1, 0, 0),
                           soadyn::Vec3<double>(0, 0, 1), 50.0, 1.0, nullptr, {0.5, 1.0, 2.0}, {-10.0, 0.0, 40.0});
    round_trip("random tree " + std::to_string(seed), model);
  }

  // Through a file.
  const std::string path = "test_model_file_cassini.json";
  soadyn::save_model(soadyn::cassini_model<double>(), path);
  check(same_dynamics(soadyn::cassini_model<double>(), soadyn::load_model(path)), "cassini through a file");
  std::remove(path.c_str());
  try {
    (void)soadyn::load_model("/nonexistent/dir/model.json");
    check(false, "loaded a missing file");
  } catch (const soadyn::ModelFileError& e) {
    check(std::string(e.what()).find("/nonexistent/dir/model.json") != std::string::npos, "missing file named");
  }

  const std::string good = soadyn::model_to_json(soadyn::four_bar_model<double>());
  refuse(good.substr(0, good.size() / 2), "not valid JSON");
  refuse("[]", "expected an object");
  refuse(replaced(good, "\"version\": 1", "\"version\": 2"), "version");
  refuse(replaced(good, "\"format\": \"soadyn-model\"", "\"format\": \"urdf\""), "format");
  refuse(replaced(good, "\"mass\": 1.5", "\"mass\": \"1.5\""), "/bodies/0/mass");
  refuse(replaced(good, "\"mass\": 1.5", "\"mass\": null"), "/bodies/0/mass");
  refuse(replaced(good, "\"mass\": 1.5", "\"mass\": -1.5"), "crank");
  refuse(replaced(good, "\"mass\": 1.5", "\"mass\": 1e999"), "not valid JSON");
  refuse(replaced(good, "\"mass\": 1.5", "\"mas\": 1.5"), "/bodies/0");
  refuse(replaced(good, "\"type\": \"revolute\"", "\"type\": \"hinge\""), "/bodies/0/joint");
  refuse(replaced(good, "\"parent\": \"crank\"", "\"parent\": \"nowhere\""), "nowhere");
  refuse(replaced(good, "\"axis\": [0.0, 0.0, 1.0]", "\"axis\": [0.0, 1.0]"), "/bodies/0/joint/axis");
  refuse(replaced(good, "\"gravity\": [0.0, -9.81, 0.0]", "\"gravity\": 9.81"), "/gravity");
  refuse(replaced(good, "\"kind\": \"revolute\"", "\"kind\": \"hinge\""), "/loops/0");
  refuse(replaced(good, "\"format\"", "\"colour\": 1, \"format\""), "colour");

  std::printf("round trips: %d models, text and dynamics identical\n", round_trips);
  std::printf("hostile texts refused with a named item: %d\n", refused);
  if (failures != 0) {
    std::printf("test_model_file: FAIL (%d)\n", failures);
    return 1;
  }
  std::printf("test_model_file: PASS\n");
  return 0;
}
