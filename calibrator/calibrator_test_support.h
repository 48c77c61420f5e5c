// What the calibrator's rig tests share beyond the test toolkit (testing/): a synthetic rig's
// observations as the pairwise stage hands them to EstimateRig.
#pragma once

#include "calibrator/rig_calibration.h"
#include "calibrator/two_view.h"
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

}  // namespace rigsim
