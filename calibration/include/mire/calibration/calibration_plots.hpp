#pragma once
// Diagnostic images of a calibration (written as PNG by `mire calibrate --report`).
#include "mire/calibration/calibrate.hpp"
#include "mire/calibration/model_check.hpp"

#include <opencv2/core.hpp>

namespace mire::calibration {

// Residual vectors (projected − observed) of every observation over the image, magnified
// (factor chosen so the 95th-percentile residual draws ≈ 3 % of the width, rounded to 1-2-5),
// with a labelled scale bar; inliers in blue, rejected points in red.
cv::Mat drawResidualMap(const CalibrationResult& result);

// One panel per used view (grid, 1500 px wide): the view's residual vectors at one magnification
// common to all panels (stated by a scale bar in the header), the view's RMS in the panel title,
// in red when above 1.5 × the overall RMS (doc/plots.md).
cv::Mat drawResidualsPerView(const CalibrationResult& result);

// Map of the projection uncertainty (projectionUncertaintyPx at the working distance, sampled every
// grid_step_px, bicubic in log10 between) on a log colour scale with 1-2-5 px contour lines and the
// observed corners of all used views as dots; the image is the camera's size plus 72 px of title
// above and 150 px of colour bar on the right (doc/plots.md).
cv::Mat drawProjectionUncertaintyMap(const CalibrationResult& result, int grid_step_px = 32);

// The model check's binned residuals (model_check.hpp): the image with the rings (equal point
// counts) and direction sectors around the principal point, each bin's mean residual as an
// arrow from the bin's centre at one magnification (scale bar), red where the bin's test rejects,
// blue where it does not, grey where too few views reach it; the verdict in the title (72 px
// above the image).
cv::Mat drawModelCheck(const CalibrationResult& result, const ModelCheck& check);

}  // namespace mire::calibration
