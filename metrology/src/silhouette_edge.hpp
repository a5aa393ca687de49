#pragma once
// The sub-pixel position of a rod's silhouette on an intensity profile across it (doc/legs.md,
// "Measuring a leg"). A matte rod lit from near the camera is darkest at its silhouette, where the
// surface grazes the ray, and its level rises as the cosine of the angle between the normal and
// the ray, √(2u/R − u²/R²) at u px inside an edge of a rod of apparent radius R: steeply (as √u).
// The gradient's maximum of such a profile lies outside the silhouette (a tenth of a pixel or
// more: a bias of the rod's apparent width, hence of its depth); fitting the profile does not.
#include <optional>
#include <vector>

namespace mire::metrology {

// Profiles across one stretch of a silhouette, each `values` sampled at `positions` (px,
// increasing along the normal into the rod, up to the rod's middle): fits, with levels of its own
// for each profile (what lies behind the rod changes along it) and u0, σ shared,
//   f(u) = B + (A − B)·Φ((u − u0)/σ) + C·(g_σ ∗ h)(u − u0),  h(x) = √(2x/R − x²/R²) for 0 ≤ x ≤ R,
// (g_σ a Gaussian of σ px: the lens, the pixel's area) with B, A, C by linear least squares for
// each (u0, σ), and (u0, σ) by Levenberg–Marquardt from (`start`, 1 px). Returns u0 and its σ
// from the residuals' scatter, or nothing when the fit does not settle within 2 px of the start
// with σ in [0.3, 3] px.
struct SilhouetteEdge {
  double position = 0.0;  // u0 [px]
  double sigma = 0.0;     // its standard deviation [px]
};
std::optional<SilhouetteEdge> silhouetteEdge(const std::vector<std::vector<double>>& positions,
                                             const std::vector<std::vector<double>>& values, double start,
                                             double radius_px);

}  // namespace mire::metrology
