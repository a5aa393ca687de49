// report.html of `mire calibrate --report` (report_html.hpp): the intrinsics with their σ first,
// then the evidence: residual vectors over the image frame, the projection uncertainty map, the
// per-view RMS, the model check, the views, the provenance.
#include "report_html.hpp"

#include "mire/report/figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace mire::app {
namespace {

namespace rp = mire::report;
namespace cal = mire::calibration;

std::string fixed(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.*f", decimals, value);
  return buffer;
}

// Axes of the image frame: u right, v down, in pixels, one pixel as long on both.
rp::Panel imageFramePanel(const cal::CalibrationResult& result) {
  rp::Panel panel;
  panel.x = rp::makeAxis("u", "px");
  panel.y = rp::makeAxis("v", "px");
  panel.x.min = 0.0, panel.x.max = result.camera.width, panel.x.tight = true;
  panel.y.min = 0.0, panel.y.max = result.camera.height, panel.y.tight = true, panel.y.inverted = true;
  panel.equal_aspect = true;
  return panel;
}

double imageFrameHeight(const cal::CalibrationResult& result, double width) {
  return 150.0 + (width - 120.0) * result.camera.height / std::max(1, result.camera.width);
}

// One full-width panel of the image frame with `field`'s vectors drawn on it.
rp::Figure imageFrameFigure(const cal::CalibrationResult& result, rp::VectorField field) {
  rp::Panel panel = imageFramePanel(result);
  panel.vectors = std::move(field);
  rp::Figure figure;
  figure.panels = {panel};
  figure.panel_width = 760.0;
  figure.panel_height = imageFrameHeight(result, figure.panel_width);
  return figure;
}

// Every used view's residuals pooled, magnified so the 95th-percentile inlier draws ≈ 3 % of the
// width (1-2-5); rejected points only when there are some.
rp::Figure residualFigure(const cal::CalibrationResult& result) {
  rp::VectorSet inliers{"inlier residuals (projected \xE2\x88\x92 observed)", {}, {}, {}, {}, "#1f77b4"};
  rp::VectorSet rejected{"rejected points", {}, {}, {}, {}, "#d62728"};
  std::vector<double> norms;
  for (const auto& view : result.views) {
    if (!view.used) continue;
    for (std::size_t k = 0; k < view.residuals.size(); ++k) {
      rp::VectorSet& set = view.inlier[k] ? inliers : rejected;
      set.x.push_back(view.pixels[k].x()), set.y.push_back(view.pixels[k].y());
      set.dx.push_back(view.residuals[k].x()), set.dy.push_back(view.residuals[k].y());
      if (view.inlier[k]) norms.push_back(view.residuals[k].norm());
    }
  }
  std::sort(norms.begin(), norms.end());
  const double p95 = norms.empty() ? 1.0 : std::max(norms[static_cast<std::size_t>(0.95 * (norms.size() - 1))], 1e-6);
  rp::VectorField field;
  field.magnification = rp::nice125(0.03 * result.camera.width / p95);
  field.unit = "px";
  field.sets = {inliers, rejected};
  return imageFrameFigure(result, std::move(field));
}

// The 1σ projection uncertainty (worst direction) at the working distance, sampled at cell
// centres every `step` px, log colour scale; the observed corners as dots (where there are none
// the map is extrapolated).
rp::Figure uncertaintyFigure(const cal::CalibrationResult& result, int step) {
  rp::HeatMap map;
  map.columns = (result.camera.width + step - 1) / step;
  map.rows = (result.camera.height + step - 1) / step;
  map.cell_width = map.cell_height = step;
  map.label = "projection uncertainty 1\xCF\x83";
  map.unit = "px";
  map.scale = rp::Scale::log10;
  for (int r = 0; r < map.rows; ++r)
    for (int c = 0; c < map.columns; ++c)
      map.values.push_back(
          cal::projectionUncertaintyPx(result, {(c + 0.5) * step, (r + 0.5) * step}, result.uncertainty_distance_m));
  rp::Series corners;
  corners.label = "observed corners";
  corners.mark = rp::Mark::points;
  corners.colour = "#000000";
  for (const auto& view : result.views)
    if (view.used)
      for (const auto& p : view.pixels) corners.x.push_back(p.x()), corners.y.push_back(p.y());
  rp::Panel panel = imageFramePanel(result);
  panel.heat_map = map;
  panel.series = {corners};
  rp::Figure figure;
  figure.panels = {panel};
  figure.panel_width = 760.0;
  figure.panel_height = imageFrameHeight(result, figure.panel_width - 90.0);
  return figure;
}

rp::Figure perViewFigure(const cal::CalibrationResult& result) {
  rp::Panel panel;
  panel.x = rp::makeAxis("view", "");
  panel.y = rp::makeAxis("RMS residual", "px");
  panel.y.include_zero = true;
  rp::Series bars;
  bars.mark = rp::Mark::bars;
  bars.colour = "#1f77b4";
  for (const auto& view : result.views) {
    if (!view.used) continue;
    bars.x.push_back(static_cast<double>(panel.categories.size()));
    bars.y.push_back(view.rms_px);
    panel.categories.push_back(view.name);
  }
  panel.series = {bars};
  panel.references = {{result.camera.rms_px, "overall RMS " + fixed(result.camera.rms_px, 3) + " px", "#333", true},
                      {1.5 * result.camera.rms_px, "1.5 \xC3\x97 overall (flagged above)", "#d62728", true}};
  rp::Figure figure;
  figure.panels = {panel};
  figure.panel_width = 760.0;
  figure.panel_height = 330.0;
  return figure;
}

// The model check's residual structure (model_check.hpp): each bin's mean residual from the bin's
// centre over the image frame at one magnification, coloured by its test (significant, not,
// untested).
rp::Figure modelCheckFigure(const cal::CalibrationResult& result, const cal::ModelCheck& check) {
  rp::VectorSet significant{"bin mean significant (views as clusters, Bonferroni)", {}, {}, {}, {}, "#d62728"};
  rp::VectorSet plain{"bin mean not significant", {}, {}, {}, {}, "#1f77b4"};
  rp::VectorSet untested{"too few views to test", {}, {}, {}, {}, "#9a9a9a"};
  double largest = 0.0;
  for (const auto& bin : check.structure.bins) {
    if (bin.points == 0) continue;
    const double radius = 0.5 * (bin.radius_min_px + bin.radius_max_px);
    const double angle = 0.5 * (bin.angle_min_rad + bin.angle_max_rad);
    rp::VectorSet& set = !bin.tested ? untested : bin.significant ? significant : plain;
    set.x.push_back(result.camera.cx() + radius * std::cos(angle));
    set.y.push_back(result.camera.cy() + radius * std::sin(angle));
    set.dx.push_back(bin.mean_px.x()), set.dy.push_back(bin.mean_px.y());
    largest = std::max(largest, bin.mean_px.norm());
  }
  const double outer =
      check.structure.ring_edges_px.empty() ? 0.5 * result.camera.width : check.structure.ring_edges_px.back();
  rp::VectorField field;
  field.magnification = rp::nice125(0.45 * outer / std::max(1, check.structure.rings) / std::max(largest, 1e-6));
  field.unit = "px";
  for (const auto* set : {&significant, &plain, &untested})
    if (!set->x.empty()) field.sets.push_back(*set);
  return imageFrameFigure(result, std::move(field));
}

bool isFixed(const cal::CalibrationResult& result, const std::string& name) {
  return std::find(result.fixed_parameters.begin(), result.fixed_parameters.end(), name) != result.fixed_parameters.end();
}

std::string pixels(double px) {
  if (!std::isfinite(px)) return "undefined";
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g px", px);
  return buffer;
}

void addResults(rp::HtmlReport& page, const cal::CalibrationResult& result,
                const cal::ProjectionUncertaintySummary& uncertainty) {
  const auto names = result.camera.parameterNames();
  const auto sigma = result.camera.sigmas();
  std::vector<rp::ResultRow> rows;
  for (std::size_t i = 0; i < names.size(); ++i) {
    const bool held = isFixed(result, names[i]);
    rows.push_back({names[i], i < 4 ? "px" : "", result.camera.params[i], held || sigma.empty() ? 0.0 : sigma[i],
                    held ? "fixed" : ""});
  }
  const auto& p = result.camera.params;
  page.lead("fx = " + rp::withSigma(p[0], sigma.empty() ? 0.0 : sigma[0]) +
            " px, fy = " + rp::withSigma(p[1], sigma.empty() ? 0.0 : sigma[1]) + " px, principal point (" +
            rp::withSigma(p[2], sigma.empty() ? 0.0 : sigma[2]) + ", " +
            rp::withSigma(p[3], sigma.empty() ? 0.0 : sigma[3]) + ") px (1\xCF\x83); reprojection RMS " +
            fixed(result.camera.rms_px, 3) + " px; projection uncertainty at " +
            fixed(result.uncertainty_distance_m * 1e3, 0) + " mm: " + pixels(uncertainty.centre_px) +
            " at the centre, " + pixels(uncertainty.corner_px) + " in the corner.");
  page.section("Result");
  page.paragraph("Model " + cal::distortionModelName(result.model) + (result.target_refined ? ", target refined" : "") +
                 "; values \xC2\xB1 1\xCF\x83 (\xCF\x83\xC2\xB2 = SSR/(2N \xE2\x88\x92 " +
                 std::to_string(result.free_parameter_count) +
                 "), inflated by the view-cluster estimate where residuals correlate within views).");
  page.results(rows);
  page.keyValues(
      {{"views used", std::to_string(result.used_views) + " (" + std::to_string(result.rejected_views) + " rejected)"},
       {"points used", std::to_string(result.used_points) + " (" + std::to_string(result.rejected_points) +
                           " rejected as outliers beyond 5\xCF\x83)"},
       {"reprojection RMS", fixed(result.camera.rms_px, 4) + " px (\xCF\x83 " + fixed(result.sigma_px, 4) + " px)"},
       {"projection uncertainty (1\xCF\x83)", "centre " + pixels(uncertainty.centre_px) + ", edge " +
                                                  pixels(uncertainty.edge_px) + ", corner " +
                                                  pixels(uncertainty.corner_px)},
       {"image", std::to_string(result.camera.width) + " \xC3\x97 " + std::to_string(result.camera.height) + " px"}});
  for (const auto& warning : result.warnings) page.paragraph("Warning: " + warning);
}

void addViews(rp::HtmlReport& page, const cal::CalibrationResult& result) {
  std::vector<std::vector<std::string>> rows;
  for (const auto& view : result.views)
    rows.push_back({view.name, view.used ? fixed(view.rms_px, 3) : "-", view.used ? fixed(view.tilt_deg, 1) : "-",
                    view.used ? "used" : view.rejection_reason});
  page.table({"view", "RMS (px)", "tilt (deg)", "status"}, rows);
}

}  // namespace

std::vector<NamedFigure> calibrateFigures(const calibration::CalibrationResult& result,
                                          const calibration::ModelCheck& check) {
  const auto residuals = residualFigure(result);
  const auto model_check = modelCheckFigure(result, check);
  return {{"residuals.svg", residuals,
           "Residual vectors of every used view over the image frame, magnified " +
               fixed(residuals.panels[0].vectors->magnification, 0) +
               " times (the scale arrow gives a true length); a swirl or a radial pattern is a model error, random "
               "directions are noise."},
          {"projection_uncertainty.svg", uncertaintyFigure(result, 32),
           "Projection uncertainty (1\xCF\x83, worst direction) at the working distance " +
               fixed(result.uncertainty_distance_m * 1e3, 0) +
               " mm, log colour scale, over the observed corners; where there are no corners the map is "
               "extrapolated."},
          {"residuals_per_view.svg", perViewFigure(result),
           "Reprojection RMS of each used view; a view above the red line deserves a look."},
          {"model_check.svg", model_check,
           "The residuals' structure over the image (doc/calibration.md, \"Model check\"): the mean residual of "
           "each of " +
               std::to_string(check.structure.rings) + " rings \xC3\x97 " + std::to_string(check.structure.sectors) +
               " directions around the principal point, from the bin's centre, magnified " +
               fixed(model_check.panels[0].vectors ? model_check.panels[0].vectors->magnification : 1.0, 0) +
               " times; red where the bin's test rejects (the mean stands out of its own spread), blue where it "
               "does not."}};
}

void writeCalibrateReportHtml(const std::filesystem::path& path, const ReportProvenance& provenance,
                              const calibration::CalibrationResult& result,
                              const calibration::ProjectionUncertaintySummary& uncertainty,
                              const calibration::ModelCheck& check) {
  rp::HtmlReport page("Camera calibration report");
  addResults(page, result, uncertainty);
  page.section("Evidence");
  const std::vector<NamedFigure> figures = calibrateFigures(result, check);
  for (std::size_t k = 0; k + 1 < figures.size(); ++k) page.figure(figures[k].figure, figures[k].caption);
  page.section("Model check");
  page.paragraph(check.verdictLine());
  page.figure(figures.back().figure, figures.back().caption);
  page.section("Views");
  addViews(page, result);
  addProvenance(page, provenance);
  writeHtml(path, page);
}

}  // namespace mire::app
