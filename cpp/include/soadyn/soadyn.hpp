// Umbrella header: the whole public C++ API for double and float.
#pragma once
#include "soadyn/algorithms/aba.hpp"
#include "soadyn/algorithms/configuration.hpp"
#include "soadyn/algorithms/crba.hpp"
#include "soadyn/algorithms/energy.hpp"
#include "soadyn/algorithms/hybrid.hpp"
#include "soadyn/algorithms/kinematics.hpp"
#include "soadyn/algorithms/rnea.hpp"
#include "soadyn/data.hpp"
#include "soadyn/model.hpp"
