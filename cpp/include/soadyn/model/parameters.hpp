// Named model parameters: read and change a built model's physical
// parameters by name, without a structural change and without allocation.
//
// A ParameterTable is built once from a model (it allocates: it holds the
// names); afterwards get() and set() allocate nothing, and set() leaves every
// quantity derived from the parameters consistent (the spatial inertia
// M(k) of Jain & Rodriguez 1993 and the tree-frame reach, tree_frame_reach.hxx).
// A set() that refuses its value throws before changing anything. The model's
// version does not change: Data built for it stays valid.
//
// Parameters (values are column-major, `rows` x `cols`):
//   <body>.mass       1      mass of a rigid body
//   <body>.com        3      centre of mass, body frame
//   <body>.inertia    3 x 3  rotational inertia about the centre of mass, body
//                            frame; symmetric to rounding (stored as given,
//                            as add_body does) and physical (check_physical_inertia
//                            in model.hxx), else NonphysicalInertiaError
//   <body>.placement  4 x 4  the joint frame in the parent body's frame as a
//                            homogeneous matrix [R p; 0 0 0 1] (for a body on
//                            a flexible body's node: in the node frame); R a
//                            proper rotation
//   gravity           3      world frame
// A body with parts welded to it by fixed joints carries their mass: its
// mass, com and inertia are those of the merged body, and a welded part has
// no parameters of its own (ParameterError naming the body it is merged
// into). A placement is the one the tree stores: for a body added on a
// welded part, the welded part's placement composed with the body's. A
// flexible body has only `<body>.placement` (its mass and modal data are left
// out). Changing a placement moves neither loop frames nor loop lengths
// (they are fixed in their bodies' frames when the loop is added).
//
// Other model elements register their parameters by appending entries (name,
// shape, index, getter, setter) in ParameterTable's constructor.
#pragma once
#include <stdexcept>
#include <string>
#include <vector>
#include "soadyn/model/model.hpp"

namespace soadyn {

// Unknown parameter, wrong size, non-finite or out-of-range value; the
// message names the parameter.
struct ParameterError : std::invalid_argument {
  using std::invalid_argument::invalid_argument;
};

template <class S>
struct ParameterEntry {
  std::string name;
  int rows = 1, cols = 1;  // shape of the value (column-major storage)
  int index = -1;          // the owner's index (a body, a force element), -1 for the model
  // Writes rows * cols values.
  void (*get)(const ModelTpl<S>& model, int index, S* out) = nullptr;
  // Validates `in` (rows * cols values) and stores it, or throws naming
  // `entry.name` and changes nothing. Allocation free when it succeeds.
  void (*set)(ModelTpl<S>& model, const ParameterEntry& entry, const S* in) = nullptr;
  int size() const { return rows * cols; }
};

template <class S>
class ParameterTable {
 public:
  explicit ParameterTable(const ModelTpl<S>& model);

  int size() const { return static_cast<int>(entries_.size()); }
  const ParameterEntry<S>& entry(int k) const { return entries_[static_cast<std::size_t>(k)]; }
  const std::vector<ParameterEntry<S>>& entries() const { return entries_; }
  // Index of `name`, -1 when absent (allocation free).
  int find(const std::string& name) const;
  // Index of `name`; throws ParameterError naming it when absent (saying
  // which body a welded part is merged into).
  int require(const ModelTpl<S>& model, const std::string& name) const;

  void get(const ModelTpl<S>& model, int k, S* out) const { entry(k).get(model, entry(k).index, out); }
  void set(ModelTpl<S>& model, int k, const S* in) const { entry(k).set(model, entry(k), in); }
  void set(ModelTpl<S>& model, const std::string& name, const S* in) const { set(model, require(model, name), in); }

  // The model version the table was built for (a structural change needs a new table).
  std::uint64_t model_version() const { return model_version_; }

 private:
  std::vector<ParameterEntry<S>> entries_;
  std::uint64_t model_version_ = 0;
};

extern template class ParameterTable<double>;
extern template class ParameterTable<float>;

}  // namespace soadyn
