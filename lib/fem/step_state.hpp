// The state of the step being solved for, owned by the time stepper (solver/simulation.cpp) and handed to the
// discretization before each solve: its terms read it (the inertia term dt and the prediction; the boundary the load;
// keyframed shape targets the time). A failed attempt is undone by handing back the last accepted state.
#pragma once

#include <petscvec.h>

namespace aries::fem {

struct StepState {
  double dt = 0.0;            // backward Euler time step; 0 for static solves (no inertia)
  double load = 0.0;          // load parameter of the prescribed motion (0 = rest, 1 = full)
  double time = 0.0;          // time of the state being solved for (static runs: step * dt)
  Vec prediction = nullptr;   // x~ = x_n + dt v_n (global, free dofs) when dt > 0; owned by the stepper
};

}  // namespace aries::fem
