// What the calibrator's rig tests share beyond the test toolkit (testing/): a synthetic rig's
// observations as the pairwise stage hands them to EstimateRig, and a result's errors against the
// truth (the calibrator never sees it; the tests do).
#pragma once

#include <vector>

#include "calibrator/rig_calibration.h"
#include "calibrator/two_view.h"
#include "evaluation/rig_scores.h"
#include "testing/synthetic_rig.h"

namespace rigsim {

struct SyntheticObservationOptions {
  TwoViewOptions two_view;
  // Also each camera between consecutive frames (RigObservations::temporal): what a moving rig
  // gives the multi-frame stages.
  bool temporal_pairs = false;
};

// Every camera pair's candidate matches per frame (SyntheticRig::CandidateMatches: the true ones
// and outliers) through EstimatePairFromMatches; with temporal_pairs, each camera's consecutive
// frames through EstimateRelativePose too.
RigObservations ObserveSyntheticRig(SyntheticRig& s, const SyntheticObservationOptions& options = {});

// Per camera, `result`'s errors against `truth` with camera 0 as the rig frame, as evaluation.json
// states them (evaluation/rig_scores.h CalibrationCameraErrors).
std::vector<CameraErrors> ErrorsAgainst(const Rig& truth, const RigCalibrationResult& result);

}  // namespace rigsim
