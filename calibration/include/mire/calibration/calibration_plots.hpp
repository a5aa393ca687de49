#pragma once
// Diagnostic images of a calibration (written as PNG by `mire calibrate --report`).
#include "mire/calibration/calibrate.hpp"

#include <opencv2/core.hpp>

namespace mire::calibration {

// Residual vectors (projected − observed) of every observation over the image, magnified
// (factor chosen so the 95th-percentile residual draws ≈ 3 % of the width, rounded to 1-2-5),
// with a labelled scale bar; inliers in blue, rejected points in red.
cv::Mat drawResidualMap(const CalibrationResult& result);

// Map of the projection uncertainty (projectionUncertaintyPx at the working distance) over
// the image, colour-coded with a labelled colour bar and the values at centre, edge, corner.
cv::Mat drawProjectionUncertaintyMap(const CalibrationResult& result, int grid_step_px = 32);

}  // namespace mire::calibration
