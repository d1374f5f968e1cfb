// Evaluation of IPT obstacle detection on labelled sequences (paper §6.1–6.2, Table 1): every
// tracked feature's D and zone against the label mask, ROC/AUC of D, the optimum β by FP + δ·FN,
// and the zone-β + refinement classifier learned leave-one-sequence-out.
#pragma once

#include <filesystem>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "squint/eval/roc.hpp"
#include "squint/obstacles/beta_learning.hpp"
#include "squint/obstacles/ipt_pipeline.hpp"

namespace squint::eval {

// One tracked feature with its ground truth.
struct ObstacleSample {
  std::size_t frame = 0;  // later frame of the pair (row in frames.csv)
  double u = 0.0, v = 0.0;
  int zone = 0;                         // 0–3
  std::optional<double> discrepancy_m;  // none above the horizon
  std::optional<double> signed_discrepancy_m;
  std::optional<double> plain_discrepancy_m;  // D of eq. 4 (discrepancy_m is the classified one)
  double previous_u = 0.0, previous_v = 0.0;  // the match in the earlier frame
  double motion_epipolar_px = 0.0;            // MeasuredFeature::motion_epipolar_px
  bool obstacle = false;                // label mask at (u, v) is not floor
};

struct SequenceSamples {
  std::string name;
  std::size_t pairs = 0;     // consecutive pairs processed
  std::size_t pairs_ok = 0;  // pairs with a classification
  std::map<std::string, std::size_t> skipped;  // status name -> pairs
  std::vector<ObstacleSample> samples;
  double mean_matches = 0.0;  // correspondences before F, per processed pair
};

// Runs the pipeline over every consecutive pair of a sequence with label masks and odometry.
// Throws squint::Error naming the sequence when it has no labels. `progress(i, n)` is optional.
SequenceSamples CollectObstacleSamples(const std::filesystem::path& sequence, const obstacles::IptOptions& options,
                                       const std::function<void(std::size_t, std::size_t)>& progress = {});

// Scores for the ROC of D: above-horizon features score +infinity (always obstacles, §4.1).
std::vector<ScoredLabel> DiscrepancyScores(const std::vector<ObstacleSample>& samples, bool below_horizon_only);
// Training samples for β (below-horizon features with a D).
std::vector<obstacles::LabelledDiscrepancy> TrainingSamples(const std::vector<ObstacleSample>& samples);

// Classification outcome of one classifier on a set of samples.
struct ClassifierScore {
  Confusion confusion;     // over classified features only
  std::size_t features = 0;    // all features
  std::size_t classified = 0;  // features given a class (the refinement leaves some out)
  double fp_per_feature = 0.0;  // FP / all features (Table 1's FP/Nbr)
  double classified_per_pair = 0.0;
};
ClassifierScore ScoreClassifier(const std::vector<ObstacleSample>& samples, std::size_t pairs_ok,
                                const obstacles::ClassifierOptions& classifier);

struct SequenceReport {
  std::string name;
  std::size_t pairs = 0, pairs_ok = 0, features = 0;
  std::map<std::string, std::size_t> skipped;
  double auc = 0.0;                    // D with above-horizon features as +inf
  double auc_below_horizon = 0.0;      // D of below-horizon features only
  double auc_plain = 0.0;              // as `auc`, for the paper's D (eq. 4)
  double single_beta_m = 0.0;          // the single β applied (learned on the other sequences)
  ClassifierScore single;              // one β, no refinement
  obstacles::ClassifierOptions zone_classifier;  // learned on the other sequences
  ClassifierScore zone;                // zone β + refinement
  Roc roc;
};

struct ObstacleEvalOptions {
  obstacles::BetaLearningOptions learning;
  // Learn β on the other sequences for each reported one (leave-one-out); with one sequence, or
  // when false, β is learned on all sequences (then reported figures are training figures).
  bool leave_one_out = true;
};

struct ObstacleEvalReport {
  std::vector<SequenceReport> sequences;
  Roc pooled_roc;           // all sequences together
  double pooled_auc_below_horizon = 0.0;
  double mean_auc = 0.0;    // mean of the per-sequence AUCs
  double mean_auc_plain = 0.0;  // the same for the paper's D (eq. 4)
  double optimum_beta_m = 0.0;  // single β minimising FP + δ·FN over all sequences
  Confusion pooled_at_optimum;  // pooled, at that β
  obstacles::ClassifierOptions zone_classifier_all;  // zone β + refinement learned on all sequences
  ClassifierScore pooled_single;  // sums of the per-sequence (held-out) results
  ClassifierScore pooled_zone;
  bool leave_one_out = false;
};

ObstacleEvalReport EvaluateObstacles(const std::vector<SequenceSamples>& sequences,
                                     const obstacles::IptOptions& options, const ObstacleEvalOptions& eval_options);

}  // namespace squint::eval
