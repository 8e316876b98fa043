// The joint types: every alternative of JointModel. Adding a joint type is
// one header beside these (joint_base.hpp lists what it provides) and its
// registration here: its #include and its entry in the variant; everything else (model, sweeps, integration, charts,
// random configurations, Python factories) dispatches on the variant.
#pragma once
#include <variant>
#include "soadyn/joints/cylindrical.hpp"
#include "soadyn/joints/fixed.hpp"
#include "soadyn/joints/free.hpp"
#include "soadyn/joints/helical.hpp"
#include "soadyn/joints/planar.hpp"
#include "soadyn/joints/prismatic.hpp"
#include "soadyn/joints/revolute.hpp"
#include "soadyn/joints/spherical.hpp"
#include "soadyn/joints/translation.hpp"
#include "soadyn/joints/universal.hpp"

namespace soadyn {

template <class S>
using JointModel = std::variant<RevoluteJoint<S>,
                                PrismaticJoint<S>,
                                HelicalJoint<S>,
                                UniversalJoint<S>,
                                CylindricalJoint<S>,
                                PlanarJoint<S>,
                                SphericalJoint<S>,
                                FreeJoint<S>,
                                FixedJoint<S>,
                                TranslationJoint<S>>;

}  // namespace soadyn
