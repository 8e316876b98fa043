// The variables of a soadyn FMU, made from its model: one table that both the FMU's binary (get and set by
// value reference) and its modelDescription.xml (written by the same binary at export) read, so the two
// cannot disagree. Names are fixed (the FMU guide lists them): time; inputs u.<dof>, locked.<dof>,
// prescribed.<dof>, wrench.<frame>.tx ... .fz; outputs q.<coordinate>, v.<dof>, qdd.<dof>, tau.<dof>,
// energy.kinetic, energy.potential, loop.<loop>.tx ... .fz (each loop's wrench), frame.<name>.x ... .az;
// parameters integrator and substeps, then the model's parameters (Model.parameter_names) element by
// element, named as a campaign names them: link_2.mass, link_2.com[2], link_2.inertia[0,1] (upper triangle:
// setting it sets its mirror), link_2.placement[1,3] (translations only), gravity[2]. Value references
// count from 0 (time) in that order.
#pragma once
#include <string>
#include <vector>

#include "soadyn/fmu/settings.hpp"
#include "soadyn/model/model.hpp"
#include "soadyn/model/parameters.hpp"

namespace soadyn::fmu {

enum class Quantity {
  time,
  input,        // u.<dof>: torque of a regular DOF, acceleration of a prescribed one
  locked,       // locked.<dof> (Boolean)
  prescribed,   // prescribed.<dof> (Boolean)
  wrench,       // wrench.<frame>.<component> (index: the wrench input, row: tx ty tz fx fy fz)
  position,     // q.<coordinate>
  velocity,     // v.<dof>
  acceleration, // qdd.<dof>
  force,        // tau.<dof>
  kinetic_energy,
  potential_energy,
  parameter,    // one element of a model parameter (Variable::tunable, or fixed)
  integrator,   // the integrator (Enumeration, fixed: kIntegrators numbered from 1)
  substeps,     // the internal steps per export step (Int32, fixed)
  frame,        // one of a named frame's outputs (index: the frame's place in the export's list, row: which)
  loop_wrench,  // one of a loop's wrench components (index: the loop, row: tx ty tz fx fy fz)
};

// A frame's outputs, in this order (row of Quantity::frame): its origin in the world (m), its orientation as a
// world quaternion (x y z w), its angular velocity and its origin's linear velocity in the frame's own axes
// (rad/s, m/s: what a gyroscope and an odometer mounted there read), and its origin's classical acceleration
// in its own axes without gravity (m/s2; an accelerometer reads this minus gravity in those axes).
inline constexpr const char* kFrameOutputs[16] = {"x",  "y",  "z",  "qx", "qy", "qz", "qw", "wx",
                                                  "wy", "wz", "vx", "vy", "vz", "ax", "ay", "az"};

enum class ValueType { float64, boolean, int32, enumeration };

struct Variable {
  std::string name;
  Quantity quantity;
  int index = -1;  // the DOF or coordinate; a parameter's entry in the model's ParameterTable
  ValueType type = ValueType::float64;
  bool start_true = false;  // a Boolean input's start value
  std::string unit;         // "" for none
  std::string description;
  int row = 0, col = 0;  // a parameter's element
  bool tunable = false;  // a parameter that may change in step mode
};

// The units of a DOF's coordinate, velocity, acceleration and generalized force: rotations in rad, rad/s,
// rad/s2, N.m; translations in m, m/s, m/s2, N; modal coordinates and quaternion entries without a unit.
struct DofUnits {
  std::string position, velocity, acceleration, force;
};
DofUnits dof_units(const Model& model, int dof);
std::string coordinate_unit(const Model& model, int coordinate);

// The variables of an FMU of `model` with `settings` (its frames, wrench inputs and input kinds).
std::vector<Variable> variables(const Model& model, const Settings& settings);

// A parameter element's value, and setting it (its symmetric mirror too): the entry's whole value is
// read into `scratch` (16 doubles), changed and set through the table, which validates it (ParameterError
// naming the parameter, nothing changed).
double parameter_element(const ParameterTable<double>& table, const Model& model, const Variable& v,
                         std::vector<double>& scratch);
void set_parameter_element(const ParameterTable<double>& table, Model& model, const Variable& v, double value,
                           std::vector<double>& scratch);

}  // namespace soadyn::fmu
