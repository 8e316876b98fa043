// The variables of a soadyn FMU, made from its model: one table that both the FMU's binary (get and set by
// value reference) and its modelDescription.xml (written by the same binary at export) read, so the two
// cannot disagree. Names are fixed (the FMU guide lists them): time; inputs u.<dof>, locked.<dof>,
// prescribed.<dof>; outputs q.<coordinate>, v.<dof>, qdd.<dof>, tau.<dof>, energy.kinetic,
// energy.potential. Value references count from 0 (time) in that order.
#pragma once
#include <string>
#include <vector>

#include "soadyn/model/model.hpp"

namespace soadyn::fmu {

enum class Quantity {
  time,
  input,        // u.<dof>: torque of a regular DOF, acceleration of a prescribed one
  locked,       // locked.<dof> (Boolean)
  prescribed,   // prescribed.<dof> (Boolean)
  position,     // q.<coordinate>
  velocity,     // v.<dof>
  acceleration, // qdd.<dof>
  force,        // tau.<dof>
  kinetic_energy,
  potential_energy,
};

struct Variable {
  std::string name;
  Quantity quantity;
  int index = -1;  // the DOF or coordinate
  bool boolean = false;
  bool start_true = false;  // a Boolean input's start value
  std::string unit;         // "" for none
  std::string description;
};

// The units of a DOF's coordinate, velocity, acceleration and generalized force: rotations in rad, rad/s,
// rad/s2, N.m; translations in m, m/s, m/s2, N; modal coordinates and quaternion entries without a unit.
struct DofUnits {
  std::string position, velocity, acceleration, force;
};
DofUnits dof_units(const Model& model, int dof);
std::string coordinate_unit(const Model& model, int coordinate);

std::vector<Variable> variables(const Model& model);

}  // namespace soadyn::fmu
