#pragma once
// Factories of the catalogued effects (one implementation file each: core/effects/effect_<id>.cpp). Callers
// outside core/effects/effects.cpp use make_effect(id) instead.
#include <memory>

#include "core/effects/effects.hpp"

namespace sb::effects {

std::unique_ptr<Effect> make_viscoelastic_creep();
std::unique_ptr<Effect> make_lens_distortion();
std::unique_ptr<Effect> make_subsurface_markers();
std::unique_ptr<Effect> make_gravity_preload();
std::unique_ptr<Effect> make_edge_constraint();
std::unique_ptr<Effect> make_load_stiffening();
std::unique_ptr<Effect> make_tracker_bias();
std::unique_ptr<Effect> make_camera_misalignment();
std::unique_ptr<Effect> make_tool_frame();
std::unique_ptr<Effect> make_pin_lever();
std::unique_ptr<Effect> make_dome_sway();
std::unique_ptr<Effect> make_spread_saturation();
std::unique_ptr<Effect> make_skin_indentation();

// Throws std::invalid_argument when disp_px and the sensor's markers differ in count.
void require_marker_count(const EffectContext& ctx, const std::vector<Vec2>& disp_px, const char* effect_id);

// The gel's outward unit normal at a point on (or near) its surface; zero where the distance has no gradient.
Vec3 gel_normal_at(const Sdf& gel_sdf_E, const Vec3& p_E);

// How deep each marker's surface point p_EM lies inside the indenter at ctx.X_EI: relu(-phi_I(X_IE p_EM)), metres
// (0 outside). Needs ctx.indenter.
std::vector<double> marker_penetration(const EffectContext& ctx);

}  // namespace sb::effects
