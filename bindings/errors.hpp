// The errors the bindings raise for results that cannot be computed. Each
// names the DOF, coordinate or body at fault (never a silent NaN).
#pragma once
#include <pybind11/pybind11.h>

#include <stdexcept>
#include <string>
#include <vector>
#include "soadyn/model/data.hpp"
#include "soadyn/core/status.hpp"

namespace soadyn_py {

// soadyn.DynamicsError (an ArithmeticError): the dynamics have no finite
// solution at the given state.
struct DynamicsError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Raises DynamicsError for a failed Status of the call `what`, naming the DOF.
void raise_on(const soadyn::Status& s, const soadyn::Model& m, const char* what);

// Raises DynamicsError naming the first of `items` items (`stride` values
// each, named by `names`) of `x` with a value that is not finite.
void refuse_non_finite(const char* what, const char* quantity, const double* x, std::size_t items, std::size_t stride,
                       const std::vector<std::string>& names);

// Raises DynamicsError naming the first row (by `row_names`) of `x` with an
// entry that is not finite: "<what>: the <quantity> of '<row>' is not finite".
void refuse_non_finite_rows(const std::string& what, const std::string& quantity,
                            const Eigen::Ref<const Eigen::MatrixXd>& x, const std::vector<std::string>& row_names);

// "loop[i]" for each closure equation, in the rows' order (names a bad
// multiplier or residual).
std::vector<std::string> loop_equation_names(const soadyn::Model& m);

// The names of the rows of a state-space matrix: each DOF's position, then
// each DOF's velocity.
std::vector<std::string> state_names(const soadyn::Model& m);

// Raises DynamicsError for a model-wide total (energy, momentum, centre of
// mass) that is not finite, naming the first body whose pose, velocity or
// share of the total is not finite, from what forward_kinematics left in `d`.
[[noreturn]] void raise_non_finite_total(const char* what, const soadyn::Model& m, const soadyn::Data& d,
                                         bool with_velocity);

// Raises DynamicsError for a potential (v null) or dissipated power (v given)
// that is not finite, naming the force element whose share is not finite or,
// when every share is, the largest share of the sum that overflows. Returns
// when the force elements' own sum is finite (they are not to blame).
void raise_non_finite_force_element(const char* what, const soadyn::Model& m, soadyn::Data& d,
                                    const Eigen::Ref<const Eigen::VectorXd>& q, const double* v);

}  // namespace soadyn_py
