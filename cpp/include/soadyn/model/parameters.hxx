// Named model parameters (templated implementation of parameters.hpp): the
// table, and the entries of rigid bodies, force elements and gravity.
#pragma once
#include <Eigen/Eigenvalues>
#include <cmath>
#include "soadyn/model/model.hxx"
#include "soadyn/model/parameters.hpp"

namespace soadyn {

namespace parameter_detail {

[[noreturn]] inline void refuse(const std::string& name, const std::string& why) {
  throw ParameterError("parameter '" + name + "': " + why);
}

template <class S>
void require_finite(const ParameterEntry<S>& e, const S* in) {
  for (int k = 0; k < e.size(); ++k)
    if (!std::isfinite(static_cast<double>(in[k]))) refuse(e.name, "value is not finite");
}

// check_physical_inertia (model.hxx) as a test: no message is built unless it fails.
template <class S>
bool is_physical(S mass, const Mat3<S>& I) {
  return detail::inertia_defect(mass, I, detail::model_tolerance<S>() * detail::inertia_scale(mass, I)) ==
         detail::InertiaDefect::none;
}

// Stores a body's mass, centre of mass and inertia about it once they are
// physical and their spatial inertia finite, then refreshes what derives from them.
template <class S>
void store_mass_properties(ModelTpl<S>& model, const ParameterEntry<S>& e, S mass, const Vec3<S>& com,
                           const Mat3<S>& inertia_com) {
  const std::size_t i = static_cast<std::size_t>(e.index);
  if (!is_physical(mass, inertia_com))
    detail::check_physical_inertia(mass, inertia_com, detail::inertia_scale(mass, inertia_com),
                                   "parameter '" + e.name + "'");
  const Mat6<S> M = spatial_inertia(mass, com, inertia_com);  // M(k), Jain & Rodriguez 1993
  if (!M.allFinite())
    refuse(e.name, "spatial inertia about the body frame origin is not finite (mass * com or mass * |com|^2 overflows)");
  model.mass[i] = mass;
  model.com[i] = com;
  model.inertia_com[i] = inertia_com;
  model.inertia[i] = M;
  model.refresh_derived_caches();
}

template <class S>
void get_mass(const ModelTpl<S>& model, int body, S* out) {
  out[0] = model.mass[static_cast<std::size_t>(body)];
}
template <class S>
void set_mass(ModelTpl<S>& model, const ParameterEntry<S>& e, const S* in) {
  require_finite(e, in);
  if (in[0] < S(0)) refuse(e.name, "mass " + detail::to_text(in[0]) + " is negative");
  const std::size_t i = static_cast<std::size_t>(e.index);
  store_mass_properties(model, e, in[0], model.com[i], model.inertia_com[i]);
}

template <class S>
void get_com(const ModelTpl<S>& model, int body, S* out) {
  Eigen::Map<Vec3<S>>{out} = model.com[static_cast<std::size_t>(body)];
}
template <class S>
void set_com(ModelTpl<S>& model, const ParameterEntry<S>& e, const S* in) {
  require_finite(e, in);
  const std::size_t i = static_cast<std::size_t>(e.index);
  store_mass_properties(model, e, model.mass[i], Vec3<S>(Eigen::Map<const Vec3<S>>(in)), model.inertia_com[i]);
}

template <class S>
void get_inertia(const ModelTpl<S>& model, int body, S* out) {
  Eigen::Map<Mat3<S>>{out} = model.inertia_com[static_cast<std::size_t>(body)];
}
template <class S>
void set_inertia(ModelTpl<S>& model, const ParameterEntry<S>& e, const S* in) {
  require_finite(e, in);
  const Mat3<S> I = Eigen::Map<const Mat3<S>>(in);
  const S tol = detail::model_tolerance<S>() * std::max(I.cwiseAbs().maxCoeff(), S(std::numeric_limits<S>::min()));
  if ((I - I.transpose()).cwiseAbs().maxCoeff() > tol) refuse(e.name, "inertia is not symmetric");
  const std::size_t i = static_cast<std::size_t>(e.index);
  store_mass_properties(model, e, model.mass[i], model.com[i], I);
}

template <class S>
void get_placement(const ModelTpl<S>& model, int body, S* out) {
  const Transform<S>& X = model.placement[static_cast<std::size_t>(body)];
  Eigen::Map<Mat4<S>> H(out);
  H.setIdentity();
  H.template topLeftCorner<3, 3>() = X.rotation;
  H.template topRightCorner<3, 1>() = X.translation;
}
template <class S>
void set_placement(ModelTpl<S>& model, const ParameterEntry<S>& e, const S* in) {
  require_finite(e, in);
  const Eigen::Map<const Mat4<S>> H(in);
  if (H(3, 0) != S(0) || H(3, 1) != S(0) || H(3, 2) != S(0) || H(3, 3) != S(1))
    refuse(e.name, "the last row of a homogeneous matrix must be (0, 0, 0, 1)");
  const Mat3<S> R = H.template topLeftCorner<3, 3>();
  const S err = (R.transpose() * R - Mat3<S>::Identity()).cwiseAbs().maxCoeff();
  if (err > detail::model_tolerance<S>() || R.determinant() < S(0))
    refuse(e.name, "rotation is not a proper rotation matrix (|R'R - I| = " + detail::to_text(err) + ")");
  Transform<S>& X = model.placement[static_cast<std::size_t>(e.index)];
  X.rotation = R;
  X.translation = H.template topRightCorner<3, 1>();
  model.refresh_derived_caches();
}

template <class S>
void get_gravity(const ModelTpl<S>& model, int, S* out) {
  Eigen::Map<Vec3<S>>{out} = model.gravity;
}
template <class S>
void set_gravity(ModelTpl<S>& model, const ParameterEntry<S>& e, const S* in) {
  require_finite(e, in);
  model.gravity = Eigen::Map<const Vec3<S>>(in);
}

// <body>.mass, .com, .inertia (rigid bodies) and <body>.placement (every body).
template <class S>
void append_body_parameters(const ModelTpl<S>& model, std::vector<ParameterEntry<S>>& entries) {
  for (int i = 0; i < model.nbodies(); ++i) {
    const std::string& body = model.body_names[static_cast<std::size_t>(i)];
    if (!model.is_flexible(i)) {
      entries.push_back({body + ".mass", 1, 1, i, &get_mass<S>, &set_mass<S>});
      entries.push_back({body + ".com", 3, 1, i, &get_com<S>, &set_com<S>});
      entries.push_back({body + ".inertia", 3, 3, i, &get_inertia<S>, &set_inertia<S>});
    }
    entries.push_back({body + ".placement", 4, 4, i, &get_placement<S>, &set_placement<S>});
  }
}

// Force elements (model/force_element.hpp): entry.index is the
// element's index among the joint springs, or nj + its index among the point
// springs (nj joint springs). Values: stiffness and damping >= 0; a joint
// spring's rest any finite value; a point spring's rest length > 0.
template <class S>
S* spring_value(ModelTpl<S>& model, int index, int field) {
  auto& f = model.force_elements;
  const int nj = static_cast<int>(f.joint_springs.size());
  if (index < nj) {
    auto& e = f.joint_springs[static_cast<std::size_t>(index)];
    return field == 0 ? &e.stiffness : field == 1 ? &e.damping : &e.rest;
  }
  auto& e = f.point_springs[static_cast<std::size_t>(index - nj)];
  return field == 0 ? &e.stiffness : field == 1 ? &e.damping : &e.rest_length;
}

template <class S, int Field>
void get_spring(const ModelTpl<S>& model, int index, S* out) {
  *out = *spring_value(const_cast<ModelTpl<S>&>(model), index, Field);
}

template <class S, int Field>
void set_spring(ModelTpl<S>& model, const ParameterEntry<S>& e, const S* in) {
  require_finite(e, in);
  const bool point = e.index >= static_cast<int>(model.force_elements.joint_springs.size());
  if (Field < 2 && *in < S(0)) refuse(e.name, "must not be negative");
  if (Field == 2 && point && !(*in > S(0))) refuse(e.name, "rest length must be positive");
  *spring_value(model, e.index, Field) = *in;
}

template <class S>
void append_spring_parameters(const ModelTpl<S>& model, std::vector<ParameterEntry<S>>& entries) {
  const auto& f = model.force_elements;
  int index = 0;
  const auto add = [&](const std::string& name, bool point) {
    entries.push_back({name + ".stiffness", 1, 1, index, &get_spring<S, 0>, &set_spring<S, 0>});
    entries.push_back({name + ".damping", 1, 1, index, &get_spring<S, 1>, &set_spring<S, 1>});
    entries.push_back({name + (point ? ".rest_length" : ".rest"), 1, 1, index, &get_spring<S, 2>, &set_spring<S, 2>});
    ++index;
  };
  for (const auto& e : f.joint_springs) add(e.name, false);
  for (const auto& e : f.point_springs) add(e.name, true);
}

}  // namespace parameter_detail

template <class S>
ParameterTable<S>::ParameterTable(const ModelTpl<S>& model) : model_version_(model.version) {
  parameter_detail::append_body_parameters(model, entries_);
  parameter_detail::append_spring_parameters(model, entries_);
  entries_.push_back({"gravity", 3, 1, -1, &parameter_detail::get_gravity<S>, &parameter_detail::set_gravity<S>});
}

template <class S>
int ParameterTable<S>::find(const std::string& name) const {
  for (std::size_t k = 0; k < entries_.size(); ++k)
    if (entries_[k].name == name) return static_cast<int>(k);
  return -1;
}

template <class S>
int ParameterTable<S>::require(const ModelTpl<S>& model, const std::string& name) const {
  const int k = find(name);
  if (k >= 0) return k;
  const std::size_t dot = name.rfind('.');
  const std::string owner = dot == std::string::npos ? name : name.substr(0, dot);
  const int f = model.frame_index(owner);
  if (f >= 0 && model.body_index(owner) < 0 && model.frames[static_cast<std::size_t>(f)].node < 0) {
    const int b = model.frames[static_cast<std::size_t>(f)].body;
    throw ParameterError("unknown parameter '" + name + "': '" + owner + "' is welded by a fixed joint to " +
                         (b < 0 ? std::string("the world") : "'" + model.body_names[static_cast<std::size_t>(b)] + "'") +
                         " and merged into it; its mass properties are part of that body's parameters");
  }
  if (model.body_index(owner) >= 0 && model.is_flexible(model.body_index(owner)))
    throw ParameterError("unknown parameter '" + name + "': flexible body '" + owner +
                         "' has only a placement parameter");
  throw ParameterError("unknown parameter '" + name + "' (see parameter_names)");
}

}  // namespace soadyn
