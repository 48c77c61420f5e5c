// The calibrator's entry: the rig from images. The pairwise stage on the views
// (stages/pairwise.h), then the rig stage (stages/rig_calibration.h) in the passes the options ask
// for: with the motion stage's links (motion_passes.h) and with refined intrinsics
// (rig_intrinsics.h).
#pragma once

#include "calibrator/features/features.h"
#include "calibrator/model/rig_observations.h"
#include "calibrator/stages/pairwise.h"
#include "calibrator/stages/rig_options.h"
#include "calibrator/stages/rig_result.h"

namespace rigsim {

// The rig stages on the pairwise stage's outcome (pairwise.h MatchRigPairs) of `views`, with the
// motion stage (motion_passes.h EstimateRigWithMotionLinks) where it applies. The
// result has the pairwise report, its pairs as the rig used them (re-estimated with the refined
// intrinsics under RigBundleAdjustmentOptions::refine_intrinsics; marked where the rig left them
// out) and, with keep_details, the match data. Throws like EstimateRig.
RigCalibrationResult EstimateRigFromPairs(const RigViews& views, const PairwiseResult& pairwise,
                                          const RigCalibrationOptions& options);

// The whole calibration of `views`: MatchRigPairs, then EstimateRigFromPairs. `keep_matches`, when
// given, receives the pairwise stage's match data (for a caller that scores or draws the matches).
// Throws std::invalid_argument on bad options or views.
RigCalibrationResult CalibrateRig(const RigViews& views, const RigCalibrationOptions& options,
                                  PairwiseMatchData* keep_matches = nullptr);

// With reestimated_pairs: result->pairwise's two-view estimates replaced by them (the report then
// shows the pairs the rig used).
void UseReestimatedPairs(RigCalibrationResult* result);

// Sets PairResult::left_out_by_rig on result->pairwise's pairs whose edge the rig stage rejected or
// found a rotation outlier: the pair's own pose is then no longer what the calibrator stands by.
void MarkPairsTheRigLeftOut(RigCalibrationResult* result);

}  // namespace rigsim
