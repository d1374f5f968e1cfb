// Two sets of seeded exploration runs compared run by run (`squint eval compare-explore`).
//
// A closed loop is chaotic: a change to the explorer reshuffles which starts meet something, so a
// variant is judged against a baseline on the same starts, run by run, over many seeds
// (docs/explore.md). A set is `squint eval explore`'s runs.csv, or a folder of seed-S/runs.csv
// folders as tools/eval_explore_seeds.sh writes them. Runs are matched by (set, world, start) and
// must start from the same pose in both.
#pragma once

#include <filesystem>
#include <limits>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace squint::eval {

struct ExploreRunRow {
  std::string set;    // "seed-S" (its folder) or "" for a single runs.csv
  std::string world;
  int start = 0;
  double x_m = 0.0, y_m = 0.0, yaw_deg = 0.0;
  double distance_m = 0.0;
  double coverage = 0.0;
  int collisions = 0;
  std::string first_hit;                                            // what was met first; empty: nothing
  double first_collision_s = std::numeric_limits<double>::quiet_NaN();  // NaN: no contact
  std::map<std::string, std::string> cells;  // every column by name, to tell a changed run
  std::string source;                        // file:line, for messages
};

// Reads PATH: a runs.csv file, a folder holding runs.csv, or a folder of seed-S/ folders each
// holding runs.csv. Throws squint::Error naming the file (and line) for a missing file or
// column, a cell that is not a number, or the same run twice.
std::vector<ExploreRunRow> LoadExploreRuns(const std::filesystem::path& path);

struct ExploreGroupComparison {
  std::string world;  // "all" for the totals
  int runs = 0;
  int changed = 0;  // runs whose shared columns differ in any cell
  double base_coverage = 0.0, new_coverage = 0.0;      // means
  double base_distance_m = 0.0, new_distance_m = 0.0;  // means
  int base_failed = 0, new_failed = 0;                 // runs with a collision
};

struct ExploreComparison {
  std::vector<ExploreGroupComparison> worlds;  // by world name
  ExploreGroupComparison all;
  // Paired coverage difference (new − base): mean and the half-width of its 95 % interval
  // (normal approximation; NaN with fewer than two runs).
  double coverage_diff_mean = 0.0;
  double coverage_diff_ci95 = std::numeric_limits<double>::quiet_NaN();
  // Runs with a collision in one set only: (base row, new row).
  std::vector<std::pair<ExploreRunRow, ExploreRunRow>> newly_failed, cleared;
  // Two-sided exact sign test (McNemar) on those discordant runs: the chance of a split at least
  // this uneven if the two sets failed equally often. 1 when there are none.
  double failure_sign_p = 1.0;
  int only_in_base = 0, only_in_new = 0;  // runs left out: not in the other set
};

// Compares the runs the two sets share. Throws squint::Error when they share none, or when a
// shared run starts from different poses (different worlds or start counts).
ExploreComparison CompareExploreRuns(const std::vector<ExploreRunRow>& base, const std::vector<ExploreRunRow>& next);

// Two-sided exact binomial sign test: P(a split of n = a + b at least as uneven as a : b | p = 1/2).
double SignTestP(int a, int b);

// The comparison as a Markdown report; base_label and new_label name the two sets.
std::string FormatExploreComparison(const ExploreComparison& c, const std::string& base_label,
                                    const std::string& new_label);

}  // namespace squint::eval
