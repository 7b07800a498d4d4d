// What the scene's cameras see now: the render scene of a (Model, State) — robot links by forward
// kinematics, the food's particles as a read-only view — and the timed render call.
#pragma once

#include "sim/render/render_scene.h"
#include "sim/render/renderer.h"
#include "sim/world/model.h"
#include "sim/world/state.h"

namespace culinarycut {

// Valid while `state` is unchanged (the food view points into the solver's particles).
// Precondition: state has been reset.
render::RenderScene MakeRenderScene(const Model& model, const State& state);

// Renders model.cameras (empty result when there are none), adds the time to Stage::kRender and
// reports it in `elapsed_ms` (ms). Throws render::RenderError.
render::RenderResult RenderCameras(render::Renderer& renderer, const Model& model, State* state, double* elapsed_ms);

}  // namespace culinarycut
