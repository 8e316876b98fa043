// Model files (model_file.hpp): the JSON writer and reader, the one
// translation unit that includes the JSON library (nlohmann/json, from the
// PyPI package nlohmann-json at build time).
#include "soadyn/model/model_file.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <initializer_list>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <variant>

#include "soadyn/joints/joint.hpp"
#include "soadyn/model/model.hxx"  // detail::check_physical_inertia

namespace soadyn {

namespace {

using json = nlohmann::ordered_json;

// ---------------------------------------------------------------- writing

json vector_json(const Eigen::Ref<const VecX<double>>& x) {
  json out = json::array();
  for (Eigen::Index k = 0; k < x.size(); ++k) out.push_back(x[k]);
  return out;
}

json matrix_json(const Eigen::Ref<const MatX<double>>& A) {  // row by row
  json out = json::array();
  for (Eigen::Index r = 0; r < A.rows(); ++r) out.push_back(vector_json(A.row(r).transpose()));
  return out;
}

json transform_json(const Transform<double>& X) {
  return json{{"rotation", matrix_json(X.rotation)}, {"translation", vector_json(X.translation)}};
}

template <class P>
json parameter_json(const P& p) {
  if constexpr (std::is_arithmetic_v<P>)
    return json(p);
  else
    return vector_json(p);
}

json joint_json(const JointModel<double>& joint, const std::string& name) {
  return std::visit(
      [&](const auto& j) {
        using J = std::decay_t<decltype(j)>;
        json out{{"type", J::name}, {"name", name}};
        constexpr std::size_t n = std::tuple_size_v<typename J::Parameters>;
        if constexpr (n == 1) {
          const auto& [a] = j;
          out[J::parameter_names[0]] = parameter_json(a);
        } else if constexpr (n == 2) {
          const auto& [a, b] = j;
          out[J::parameter_names[0]] = parameter_json(a);
          out[J::parameter_names[1]] = parameter_json(b);
        }
        return out;
      },
      joint);
}

json flexible_json(const FlexibleBody& body) {
  json nodes = json::array();
  for (int j = 0; j < body.n_nodes(); ++j) {
    const FlexibleNode<double>& node = body.node(j);
    nodes.push_back(json{{"position", vector_json(node.position)},
                         {"mass", node.mass},
                         {"rotary_inertia", matrix_json(node.rotary_inertia)},
                         {"mode_shape", matrix_json(node.mode_shape)}});
  }
  json attachments = json::object();
  for (const auto& [name, node] : body.attachments()) attachments[name] = node;
  return json{{"nodes", nodes},
              {"stiffness", matrix_json(body.stiffness())},
              {"damping", matrix_json(body.damping())},
              {"attachments", attachments}};
}

// The name a child uses for body i's parent: the parent body, the world, or
// the attachment frame of a flexible parent's node.
std::string parent_name(const Model& m, int i) {
  const int p = m.parent[static_cast<std::size_t>(i)];
  if (p < 0) return "world";
  const int node = m.attachment_node[static_cast<std::size_t>(i)];
  if (node < 0) return m.body_names[static_cast<std::size_t>(p)];
  for (const auto& [attachment, j] : m.flexible_body(p).attachments())
    if (j == node) return m.body_names[static_cast<std::size_t>(p)] + ":" + attachment;
  throw ModelFileError("body '" + m.body_names[static_cast<std::size_t>(i)] + "' sits on a node without attachment");
}

bool physical(const Model& m, std::size_t i) {
  try {
    detail::check_physical_inertia(m.mass[i], m.inertia_com[i], detail::inertia_scale(m.mass[i], m.inertia_com[i]),
                                   m.body_names[i]);
    return true;
  } catch (const NonphysicalInertiaError&) {
    return false;
  }
}

json body_json(const Model& m, int index) {
  const std::size_t i = static_cast<std::size_t>(index);
  json body{{"name", m.body_names[i]},
            {"parent", parent_name(m, index)},
            {"joint", joint_json(m.joints[i], m.joint_names[i])},
            {"placement", transform_json(m.placement[i])}};
  if (m.is_flexible(index)) {
    body["flexible"] = flexible_json(m.flexible_body(index));
    return body;
  }
  body["mass"] = m.mass[i];
  body["com"] = vector_json(m.com[i]);
  body["inertia"] = matrix_json(m.inertia_com[i]);
  body["spatial_inertia"] = matrix_json(m.inertia[i]);
  if (!physical(m, i)) body["accept_nonphysical_inertia"] = true;
  return body;
}

json force_elements_json(const Model& m, json& point_springs) {
  json joint_springs = json::array();
  for (const JointSpringTpl<double>& e : m.force_elements.joint_springs)
    joint_springs.push_back(json{{"name", e.name},
                                 {"dof", m.dof_names[static_cast<std::size_t>(e.dof)]},
                                 {"stiffness", e.stiffness},
                                 {"damping", e.damping},
                                 {"rest", e.rest}});
  point_springs = json::array();
  for (const PointSpringTpl<double>& e : m.force_elements.point_springs) {
    const auto body = [&](int b) { return b < 0 ? std::string("world") : m.body_names[static_cast<std::size_t>(b)]; };
    json spring{{"name", e.name},        {"frame_a", body(e.body_a)},      {"point_a", vector_json(e.point_a)},
                {"frame_b", body(e.body_b)}, {"point_b", vector_json(e.point_b)}, {"stiffness", e.stiffness},
                {"damping", e.damping},  {"rest_length", e.rest_length}};
    if (!e.force_law.empty())
      spring["force_law"] = json{{"lengths", e.force_law.length}, {"forces", e.force_law.force}};
    point_springs.push_back(spring);
  }
  return joint_springs;
}

// ---------------------------------------------------------------- reading

// A JSON value with its path, for errors that name the item.
struct Item {
  const json& value;
  std::string path;
  const std::string& source;

  [[noreturn]] void fail(const std::string& what) const {
    throw ModelFileError(source + ": " + (path.empty() ? "/" : path) + ": " + what);
  }
  Item at(const std::string& key) const {
    if (!value.is_object()) fail("expected an object");
    const auto it = value.find(key);
    if (it == value.end()) fail("missing key '" + key + "'");
    return Item{*it, path + "/" + key, source};
  }
  bool has(const std::string& key) const { return value.is_object() && value.contains(key); }
  Item at(std::size_t k) const { return Item{value.at(k), path + "/" + std::to_string(k), source}; }
  std::size_t size() const {
    if (!value.is_array()) fail("expected an array");
    return value.size();
  }
  void only(std::initializer_list<const char*> keys) const {
    if (!value.is_object()) fail("expected an object");
    const std::set<std::string> allowed(keys.begin(), keys.end());
    for (const auto& [key, _] : value.items())
      if (!allowed.count(key)) fail("unknown key '" + key + "'");
  }
  std::string text() const {
    if (!value.is_string()) fail("expected a string");
    return value.get<std::string>();
  }
  double number() const {
    if (!value.is_number()) fail("expected a number");
    const double x = value.get<double>();
    if (!std::isfinite(x)) fail("not finite");
    return x;
  }
  int integer() const {
    if (!value.is_number_integer()) fail("expected an integer");
    return value.get<int>();
  }
  bool boolean() const {
    if (!value.is_boolean()) fail("expected true or false");
    return value.get<bool>();
  }
  VecX<double> vector(Eigen::Index n = -1) const {
    const std::size_t count = size();
    if (n >= 0 && static_cast<Eigen::Index>(count) != n) fail("expected " + std::to_string(n) + " numbers");
    VecX<double> out(static_cast<Eigen::Index>(count));
    for (std::size_t k = 0; k < count; ++k) out[static_cast<Eigen::Index>(k)] = at(k).number();
    return out;
  }
  MatX<double> matrix(Eigen::Index rows = -1, Eigen::Index cols = -1) const {
    const std::size_t r = size();
    if (rows >= 0 && static_cast<Eigen::Index>(r) != rows) fail("expected " + std::to_string(rows) + " rows");
    MatX<double> out;
    for (std::size_t k = 0; k < r; ++k) {
      const VecX<double> row = at(k).vector(cols >= 0 ? cols : (k == 0 ? -1 : out.cols()));
      if (k == 0) out.resize(static_cast<Eigen::Index>(r), row.size());
      out.row(static_cast<Eigen::Index>(k)) = row.transpose();
    }
    if (r == 0) out.resize(0, cols >= 0 ? cols : 0);
    return out;
  }
  Transform<double> transform() const {
    only({"rotation", "translation"});
    Transform<double> X;
    X.rotation = at("rotation").matrix(3, 3);
    X.translation = at("translation").vector(3);
    return X;
  }
};

template <class P>
P parameter_from(const Item& item) {
  if constexpr (std::is_arithmetic_v<P>)
    return static_cast<P>(item.number());
  else
    return P(item.vector(P::RowsAtCompileTime));
}

template <class J>
bool try_joint(const Item& item, const std::string& type, JointModel<double>& out) {
  if (type != J::name) return false;
  using Parameters = typename J::Parameters;
  constexpr std::size_t n = std::tuple_size_v<Parameters>;
  if constexpr (n == 0) {
    item.only({"type", "name"});
    out = J{};
  } else if constexpr (n == 1) {
    item.only({"type", "name", J::parameter_names[0]});
    out = J{parameter_from<std::tuple_element_t<0, Parameters>>(item.at(J::parameter_names[0]))};
  } else {
    item.only({"type", "name", J::parameter_names[0], J::parameter_names[1]});
    out = J{parameter_from<std::tuple_element_t<0, Parameters>>(item.at(J::parameter_names[0])),
            parameter_from<std::tuple_element_t<1, Parameters>>(item.at(J::parameter_names[1]))};
  }
  return true;
}

template <class... J>
JointModel<double> joint_from(const Item& item, std::variant<J...>*) {
  const std::string type = item.at("type").text();
  JointModel<double> out;
  if (!(try_joint<J>(item, type, out) || ...)) item.at("type").fail("unknown joint type '" + type + "'");
  return out;
}

FlexibleBody flexible_from(const Item& item) {
  item.only({"nodes", "stiffness", "damping", "attachments"});
  FlexibleBodyDescription<double> d;
  const Item nodes = item.at("nodes");
  for (std::size_t k = 0; k < nodes.size(); ++k) {
    const Item node = nodes.at(k);
    node.only({"position", "mass", "rotary_inertia", "mode_shape"});
    FlexibleNode<double> n;
    n.position = node.at("position").vector(3);
    n.mass = node.at("mass").number();
    n.rotary_inertia = node.at("rotary_inertia").matrix(3, 3);
    n.mode_shape = node.at("mode_shape").matrix(6);
    d.nodes.push_back(n);
  }
  d.stiffness = item.at("stiffness").matrix();
  d.damping = item.at("damping").matrix();
  const Item attachments = item.at("attachments");
  if (!attachments.value.is_object()) attachments.fail("expected an object");
  for (const auto& [name, _] : attachments.value.items()) d.attachments[name] = attachments.at(name).integer();
  try {
    return FlexibleBody(d);
  } catch (const std::invalid_argument& e) {
    item.fail(e.what());
  }
}

void add_body_from(Model& m, const Item& body, std::vector<Item>& inertias) {
  body.only({"name", "parent", "joint", "placement", "mass", "com", "inertia", "spatial_inertia",
             "accept_nonphysical_inertia", "flexible"});
  const std::string name = body.at("name").text(), parent = body.at("parent").text();
  const Item joint_item = body.at("joint");
  const JointModel<double> joint = joint_from(joint_item, static_cast<JointModel<double>*>(nullptr));
  const std::string joint_name = joint_item.has("name") ? joint_item.at("name").text() : name;
  const Transform<double> X = body.at("placement").transform();
  try {
    if (body.has("flexible")) {
      m.add_flexible_body(name, parent, joint, X, flexible_from(body.at("flexible")), joint_name);
      return;
    }
    const bool accept = body.has("accept_nonphysical_inertia") && body.at("accept_nonphysical_inertia").boolean();
    const double mass = body.at("mass").number();
    const Vec3<double> com = body.at("com").vector(3);
    const Mat3<double> inertia = body.at("inertia").matrix(3, 3);
    m.add_body(name, parent, joint, X, mass, com, inertia, joint_name,
               accept ? InertiaPolicy::accept_nonphysical : InertiaPolicy::require_physical);
    inertias.push_back(body);
  } catch (const ModelFileError&) {
    throw;
  } catch (const std::invalid_argument& e) {
    body.fail(e.what());
  }
}

// After every body and frame is in: the bodies' inertias exactly as written
// (a welded part's merge, redone, could differ in the last bit).
void restore_inertias(Model& m, const std::vector<Item>& bodies) {
  for (const Item& body : bodies) {
    const std::size_t i = static_cast<std::size_t>(m.body_index(body.at("name").text()));
    m.mass[i] = body.at("mass").number();
    m.com[i] = body.at("com").vector(3);
    m.inertia_com[i] = body.at("inertia").matrix(3, 3);
    const Mat6<double> computed = spatial_inertia(m.mass[i], m.com[i], m.inertia_com[i]);
    if (!body.has("spatial_inertia")) {
      m.inertia[i] = computed;
      continue;
    }
    const Mat6<double> written = body.at("spatial_inertia").matrix(6, 6);
    if ((written - computed).cwiseAbs().maxCoeff() > 1e-9 * std::max(1.0, computed.cwiseAbs().maxCoeff()))
      body.at("spatial_inertia").fail("does not agree with mass, com and inertia");
    m.inertia[i] = written;
  }
  m.refresh_derived_caches();
}

void add_frame_from(Model& m, const Item& frame) {
  frame.only({"name", "body", "placement"});
  try {
    m.add_body(frame.at("name").text(), frame.at("body").text(), FixedJoint<double>{},
               frame.at("placement").transform(), 0.0, Vec3<double>::Zero(), Mat3<double>::Zero());
  } catch (const std::invalid_argument& e) {
    frame.fail(e.what());
  }
}

void add_loop_from(Model& m, const Item& loop) {
  loop.only({"name", "kind", "frame_a", "placement_a", "frame_b", "placement_b", "length"});
  const std::string name = loop.at("name").text();
  try {
    const LoopKind kind = parse_loop_kind(loop.at("kind").text(), name);
    const std::string b = loop.at("frame_b").text();
    m.add_loop(name, loop.at("frame_a").text(), b == "world" ? "" : b, kind, loop.at("placement_a").transform(),
               loop.at("placement_b").transform(), loop.at("length").number());
  } catch (const ModelFileError&) {
    throw;
  } catch (const std::exception& e) {
    loop.fail(e.what());
  }
}

int dof_of(const Model& m, const Item& item) {
  const int dof = m.dof_index(item.text());
  if (dof < 0) item.fail("unknown DOF '" + item.text() + "'");
  return dof;
}

void add_force_elements_from(Model& m, const Item& joint_springs, const Item& point_springs) {
  for (std::size_t k = 0; k < joint_springs.size(); ++k) {
    const Item e = joint_springs.at(k);
    e.only({"name", "dof", "stiffness", "damping", "rest"});
    try {
      m.add_joint_spring(e.at("name").text(), dof_of(m, e.at("dof")), e.at("stiffness").number(),
                         e.at("damping").number(), e.at("rest").number());
    } catch (const std::invalid_argument& x) {
      if (dynamic_cast<const ModelFileError*>(&x)) throw;
      e.fail(x.what());
    }
  }
  for (std::size_t k = 0; k < point_springs.size(); ++k) {
    const Item e = point_springs.at(k);
    e.only({"name", "frame_a", "point_a", "frame_b", "point_b", "stiffness", "damping", "rest_length", "force_law"});
    std::vector<double> lengths, forces;
    if (e.has("force_law")) {
      const Item law = e.at("force_law");
      law.only({"lengths", "forces"});
      const VecX<double> L = law.at("lengths").vector(), F = law.at("forces").vector();
      lengths.assign(L.data(), L.data() + L.size());
      forces.assign(F.data(), F.data() + F.size());
    }
    const double rest = e.at("rest_length").number();
    const auto frame = [](const std::string& f) { return f == "world" ? std::string() : f; };
    try {
      m.add_point_spring(e.at("name").text(), frame(e.at("frame_a").text()), frame(e.at("frame_b").text()),
                         e.at("point_a").vector(3), e.at("point_b").vector(3), e.at("stiffness").number(),
                         e.at("damping").number(), &rest, lengths, forces);
    } catch (const std::invalid_argument& x) {
      if (dynamic_cast<const ModelFileError*>(&x)) throw;
      e.fail(x.what());
    }
  }
}

// {DOF name: value} of `item` through `set` (Model::set_armature, ...); an
// unknown DOF or a value `set` refuses fails naming the entry.
void read_dof_values(Model& m, const Item& item, void (Model::*set)(int, double)) {
  if (!item.value.is_object()) item.fail("expected an object");
  for (const auto& [name, _] : item.value.items()) {
    const Item value = item.at(name);
    const int dof = m.dof_index(name);
    if (dof < 0) value.fail("unknown DOF '" + name + "'");
    try {
      (m.*set)(dof, value.number());
    } catch (const std::invalid_argument& e) {
      if (dynamic_cast<const ModelFileError*>(&e)) throw;
      value.fail(e.what());
    }
  }
}

Model model_from(const json& root, const std::string& source) {
  const Item top{root, "", source};
  top.only({"format", "version", "gravity", "bodies", "frames", "loops", "joint_springs", "point_springs",
            "prescribed", "armature", "effort_limits", "description"});
  if (top.at("format").text() != "soadyn-model") top.at("format").fail("expected \"soadyn-model\"");
  const int version = top.at("version").integer();
  if (version < 1 || version > model_file_version)
    top.at("version").fail("version " + std::to_string(version) + " is not one this build reads (1 to " +
                           std::to_string(model_file_version) + ")");
  Model m;
  m.gravity = top.at("gravity").vector(3);
  std::vector<Item> rigid;
  const Item bodies = top.at("bodies");
  for (std::size_t k = 0; k < bodies.size(); ++k) add_body_from(m, bodies.at(k), rigid);
  const Item frames = top.at("frames");
  for (std::size_t k = 0; k < frames.size(); ++k) add_frame_from(m, frames.at(k));
  restore_inertias(m, rigid);
  const Item loops = top.at("loops");
  for (std::size_t k = 0; k < loops.size(); ++k) add_loop_from(m, loops.at(k));
  add_force_elements_from(m, top.at("joint_springs"), top.at("point_springs"));
  const Item prescribed = top.at("prescribed");
  for (std::size_t k = 0; k < prescribed.size(); ++k) {
    const int dof = dof_of(m, prescribed.at(k));
    if (m.is_modal(dof)) prescribed.at(k).fail("a modal DOF cannot be prescribed");
    m.set_prescribed(dof, true);
  }
  read_dof_values(m, top.at("armature"), &Model::set_armature);
  if (root.contains("effort_limits")) read_dof_values(m, top.at("effort_limits"), &Model::set_effort_limit);
  const Item description = top.at("description");
  if (!description.value.is_object()) description.fail("expected an object");
  m.description = description.value.dump();
  return m;
}

// The layout of the text: one key per line, a vector on one line, a matrix
// one row per line (nlohmann's own indented dump puts every number on a
// line of its own, which no reader can scan).
void write_layout(const json& value, int depth, std::string& out) {
  const auto indent = [&](int d) { out.append(static_cast<std::size_t>(2 * d), ' '); };
  const bool is_container = value.is_object() || value.is_array();
  if (!is_container || value.empty()) {
    out += value.dump();
    return;
  }
  const bool flat = value.is_array() && std::none_of(value.begin(), value.end(), [](const json& e) {
                      return e.is_object() || (e.is_array() && !e.empty());
                    });
  if (flat) {
    out += '[';
    for (std::size_t k = 0; k < value.size(); ++k) out += (k ? ", " : "") + value[k].dump();
    out += ']';
    return;
  }
  out += value.is_object() ? "{\n" : "[\n";
  bool first = true;
  for (const auto& [key, element] : value.items()) {
    if (!first) out += ",\n";
    first = false;
    indent(depth + 1);
    if (value.is_object()) out += json(key).dump() + ": ";
    write_layout(element, depth + 1, out);
  }
  out += '\n';
  indent(depth);
  out += value.is_object() ? '}' : ']';
}

}  // namespace

std::string model_to_json(const Model& m) {
  json bodies = json::array(), frames = json::array(), loops = json::array(), point_springs;
  for (int i = 0; i < m.nbodies(); ++i) bodies.push_back(body_json(m, i));
  for (const Frame<double>& f : m.frames) {
    if (f.node >= 0) continue;  // a flexible body's attachment frame: made by the body itself
    frames.push_back(json{{"name", f.name},
                          {"body", f.body < 0 ? std::string("world") : m.body_names[static_cast<std::size_t>(f.body)]},
                          {"placement", transform_json(f.placement)}});
  }
  for (const LoopTpl<double>& l : m.loops) {
    const auto body = [&](int b) { return b < 0 ? std::string("world") : m.body_names[static_cast<std::size_t>(b)]; };
    loops.push_back(json{{"name", l.name},
                         {"kind", loop_kind_name(l.kind)},
                         {"frame_a", body(l.body_a)},
                         {"placement_a", transform_json(l.placement_a)},
                         {"frame_b", body(l.body_b)},
                         {"placement_b", transform_json(l.placement_b)},
                         {"length", l.length}});
  }
  const json joint_springs = force_elements_json(m, point_springs);
  json prescribed = json::array(), armature = json::object(), effort_limits = json::object();
  for (int k = 0; k < m.nv; ++k) {
    const std::size_t d = static_cast<std::size_t>(k);
    if (m.is_prescribed(k)) prescribed.push_back(m.dof_names[d]);
    if (m.armature[d] != 0.0) armature[m.dof_names[d]] = m.armature[d];
    if (std::isfinite(m.effort_limit[d])) effort_limits[m.dof_names[d]] = m.effort_limit[d];
  }
  json description = json::parse(m.description.empty() ? std::string("{}") : m.description, nullptr, false);
  if (description.is_discarded() || !description.is_object())
    throw ModelFileError("the model's description is not a JSON object");
  json root{{"format", "soadyn-model"}, {"version", model_file_version}, {"gravity", vector_json(m.gravity)},
            {"bodies", bodies},         {"frames", frames},            {"loops", loops},
            {"joint_springs", joint_springs}, {"point_springs", point_springs},
            {"prescribed", prescribed}, {"armature", armature}};
  if (!effort_limits.empty()) root["effort_limits"] = effort_limits;  // optional: files without limits read anywhere
  root["description"] = description;
  std::string text;
  write_layout(root, 0, text);
  return text;
}

namespace {

// The length of the well-formed UTF-8 sequence starting at text[i] (RFC 3629:
// no overlong forms, no surrogates, nothing past U+10FFFF), or 0.
std::size_t utf8_sequence_length(const std::string& text, std::size_t i) {
  const auto byte = [&](std::size_t k) { return k < text.size() ? static_cast<unsigned char>(text[k]) : 0u; };
  const unsigned lead = byte(i);
  if (lead < 0x80) return 1;
  const std::size_t length = lead >= 0xC2 && lead <= 0xDF ? 2 : lead >= 0xE0 && lead <= 0xEF ? 3
                             : lead >= 0xF0 && lead <= 0xF4 ? 4 : 0;
  if (length == 0) return 0;
  const unsigned second = byte(i + 1);
  const unsigned low = lead == 0xE0 ? 0xA0 : lead == 0xF0 ? 0x90 : 0x80;
  const unsigned high = lead == 0xED ? 0x9F : lead == 0xF4 ? 0x8F : 0xBF;
  if (second < low || second > high) return 0;
  for (std::size_t k = 2; k < length; ++k)
    if ((byte(i + k) & 0xC0u) != 0x80u) return 0;
  return length;
}

// `text` with each byte outside a well-formed UTF-8 sequence replaced by '?':
// a JSON parse error quotes the bytes it last read, which may end inside a
// multibyte character, and a message must decode as text wherever it goes.
std::string valid_utf8(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t length = utf8_sequence_length(text, i);
    if (length == 0) {
      out += '?';
      ++i;
    } else {
      out.append(text, i, length);
      i += length;
    }
  }
  return out;
}

}  // namespace

Model model_from_json(const std::string& text, const std::string& source) {
  if (text.size() > model_file_max_bytes)
    throw ModelFileError(source + ": " + std::to_string(text.size()) + " bytes, more than the limit of " +
                         std::to_string(model_file_max_bytes) + " bytes of a model file");
  // The parser calls back as each array or object opens with the number of
  // those around it (0 for the outermost); the (max + 1)-th level stops it
  // before the tree is built (model_file_max_depth).
  const json::parser_callback_t bounded_depth = [&](int depth, json::parse_event_t event, json&) {
    const bool opens = event == json::parse_event_t::object_start || event == json::parse_event_t::array_start;
    if (opens && depth >= model_file_max_depth)
      throw ModelFileError(source + ": JSON nested deeper than the limit of " + std::to_string(model_file_max_depth) +
                           " levels");
    return true;
  };
  json root;
  try {
    root = json::parse(text, bounded_depth);
  } catch (const json::exception& e) {  // a syntax error, or a number beyond double's range
    throw ModelFileError(source + ": not valid JSON: " + valid_utf8(e.what()));
  }
  try {
    return model_from(root, source);
  } catch (const ModelFileError&) {
    throw;
  } catch (const json::exception& e) {
    throw ModelFileError(source + ": " + valid_utf8(e.what()));
  }
}

void save_model(const Model& model, const std::string& path) {
  const std::string text = model_to_json(model);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw ModelFileError("model file '" + path + "': cannot be written");
  out << text << '\n';
  if (!out.flush()) throw ModelFileError("model file '" + path + "': cannot be written");
}

Model load_model(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw ModelFileError("model file '" + path + "' cannot be read");
  in.seekg(0, std::ios::end);
  const std::streamoff size = in.tellg();
  if (size > static_cast<std::streamoff>(model_file_max_bytes))
    throw ModelFileError("model file '" + path + "': " + std::to_string(size) + " bytes, more than the limit of " +
                         std::to_string(model_file_max_bytes) + " bytes of a model file");
  in.seekg(0, std::ios::beg);
  std::ostringstream text;
  text << in.rdbuf();
  return model_from_json(text.str(), "model file '" + path + "'");
}

}  // namespace soadyn
