// The reference path the motion controllers follow is planning's output
// (controller/planning/path.h: stations, conventions, projection); motion names it as its own.
#pragma once

#include "controller/planning/path.h"

namespace scw::controller::motion {

using planning::Path;
using planning::PathPoint;
using planning::PathProjection;
using planning::WrapAngle;

}  // namespace scw::controller::motion
