// What the scene's cameras see now: the render scene of a (Model, State) — robot links by forward
// kinematics, the food's particles as a read-only view. Observe (observation.h) renders it.
#pragma once

#include "sim/render/render_scene.h"
#include "sim/world/model.h"
#include "sim/world/state.h"

namespace culinarycut {

// Valid while `state` is unchanged (the food view points into the solver's particles).
// Precondition: state has been reset.
render::RenderScene MakeRenderScene(const Model& model, const State& state);


}  // namespace culinarycut
