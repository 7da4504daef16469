// ruled_model.hpp — a ruled-surface piece through set points, the seed paper's section 4
// (eqs. 13-17): the tool positions a_i become the Ferguson directrix, the tool axes A_i the
// ruling (as the spherical angles (theta_i, phi_i), eq. 16, or as the vectors themselves).
// This is what a program listing directrix points and tool vectors gives the host.
//
// Tangents: each set point's derivatives with respect to the directrix's chord length l are
// estimated by the three-point formula on uneven spacing (dc/dl, d(ruling)/dl); segment i,
// of chord L_i, takes L_i times them at both ends. Directrix and ruling then share one
// scale per segment, so the velocity c_u du/dt and the ruling's rate e_u du/dt are
// continuous across set points (du/dt = F / |c_u| changes there, the motion does not); the
// second derivatives jump at set points, as with any Ferguson chain.
#pragma once

#include <string>
#include <vector>

#include "geometry/hermite_curve.hpp"
#include "geometry/ruled_surface.hpp"
#include "geometry/vec3.hpp"

namespace pcnc {

/// The owned curves of a piece; curves() views them (the model must outlive the view).
struct RuledModel {
  std::vector<HermiteSegment> directrix;
  std::vector<HermiteSegment> ruling;  // (theta, phi, 0) or vectors, per `form`
  RulingForm form = RulingForm::kAngles;

  RuledCurves curves() const;
};

/// The three-point derivative estimates df/dl at every sample (l strictly increasing, >= 2
/// samples; two samples give the chord's slope).
std::vector<Vec3> chord_derivatives(const std::vector<double>& l, const std::vector<Vec3>& f);

/// The piece through set points (>= 2) and unit tool vectors (one per point; normalised
/// here). Empty `error` when built; otherwise it says why (sizes, coinciding points, a
/// zero vector).
struct RuledModelResult {
  RuledModel model;
  std::string error;
};
RuledModelResult ruled_model_through(const std::vector<Vec3>& points, const std::vector<Vec3>& tool_vectors,
                                     RulingForm form = RulingForm::kAngles);

}  // namespace pcnc
