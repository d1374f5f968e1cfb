// End-to-end `squint explore`: a short run writes summary.json (all keys), map.png and trace.csv;
// a T world's side branch met from the bar is taken; bad input (unknown world, non-positive
// minutes) is one clear error line and no output folder.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "cli_run.hpp"

namespace {

using squint::test::CliResult;
using squint::test::RunSquint;

std::filesystem::path TempDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("squint_apps_explore_" + name);
  std::filesystem::remove_all(dir);
  return dir;
}

// `squint explore ARGS --out OUT` must succeed; its summary.json.
nlohmann::json ExploreSummary(const std::filesystem::path& out, const std::string& args) {
  const CliResult r = RunSquint("explore " + args + " --out " + out.string());
  EXPECT_EQ(r.code, 0) << r.all();
  std::ifstream js(out / "summary.json");
  return nlohmann::json::parse(js);
}

TEST(ExploreCli, ShortRunWritesTheThreeOutputs) {
  const auto out = TempDir("short");
  const CliResult r = RunSquint("explore --world corridor-0 --minutes 0.5 --seed 2 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.all();
  std::ifstream js(out / "summary.json");
  const nlohmann::json j = nlohmann::json::parse(js);
  for (const char* key : {"sim_seconds", "distance_m", "collisions", "coverage", "ends_detected", "turns", "frames",
                          "frames_fully_processed", "perception_cpu_seconds", "wall_seconds", "setoff_seconds",
                          "setoff_axis_error_deg", "axis_error_p90_deg", "axis_error_over_10deg", "first_collision_s",
                          "first_collision_x_m", "first_collision_y_m", "first_hit", "mirror_scans", "contacts_felt"})
    EXPECT_TRUE(j.contains(key)) << key;
  EXPECT_NEAR(j["sim_seconds"].get<double>(), 30.0, 0.1);
  EXPECT_EQ(j["frames"].get<long>(), 900);
  EXPECT_GT(j["distance_m"].get<double>(), 1.0);
  EXPECT_TRUE(std::filesystem::exists(out / "map.png"));
  EXPECT_TRUE(std::filesystem::exists(out / "trace.csv"));
  std::filesystem::remove_all(out);
}

// `squint eval explore`: runs.csv's header (the last four columns against ground truth), one row per
// start, and the table's footer lines.
TEST(ExploreCli, EvalExploreWritesTheRunsTableAndTheAxisFigures) {
  const auto out = TempDir("eval");
  const CliResult r = RunSquint("eval explore --world corridor-0 --starts 2 --minutes 0.4 --seed 3 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.all();
  std::ifstream csv(out / "runs.csv");
  std::string line;
  std::getline(csv, line);
  EXPECT_EQ(line,
            "world,start,x_m,y_m,yaw_deg,sim_seconds,distance_m,coverage,ends_detected,turns,collisions,proceeded,"
            "setoff_s,setoff_axis_error_deg,axis_error_p90_deg,axis_error_over_10deg,first_collision_s,first_hit,"
            "mirror_scans,contacts_felt,near_edges,align_line_overrides,scan_entropy_skips,wall_keep_frames,"
            "scan_wall_entropy_skips");
  int rows = 0;
  while (std::getline(csv, line)) {
    ++rows;
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (!line.empty() && line.back() == ',') cells.emplace_back();
    ASSERT_EQ(cells.size(), 25u) << line;
    EXPECT_EQ(cells[0], "corridor-0");
    EXPECT_EQ(cells[18], "0") << line;  // no mirror in corridor-0 (mirror_scans)
    EXPECT_GE(std::stol(cells[20]), 0) << line;  // near_edges: a count
    EXPECT_GE(std::stol(cells[21]), 0) << line;  // align_line_overrides: a count
    EXPECT_GE(std::stol(cells[22]), 0) << line;  // scan_entropy_skips: a count
    EXPECT_GE(std::stol(cells[23]), 0) << line;  // wall_keep_frames: a count
    EXPECT_GE(std::stol(cells[24]), 0) << line;  // scan_wall_entropy_skips: a count
    if (cells[10] == "0") {
      EXPECT_EQ(cells[19], "0") << line;  // no contact felt without a collision (contacts_felt)
    }
    // Start 0 is the world's start, along the axis: it sets off within seconds, nearly on the axis.
    if (cells[1] == "0") {
      ASSERT_FALSE(cells[12].empty()) << line;
      EXPECT_LT(std::stod(cells[12]), 5.0) << line;
      EXPECT_LT(std::abs(std::stod(cells[13])), 5.0) << line;
      const double over = std::stod(cells[15]);
      EXPECT_GE(over, 0.0);
      EXPECT_LE(over, 1.0);
    }
    // No contact, no first contact; a contact names what was touched.
    EXPECT_EQ(cells[10] == "0", cells[16].empty() && cells[17].empty()) << line;
  }
  EXPECT_EQ(rows, 2);
  std::ifstream md(out / "table.md");
  const std::string table((std::istreambuf_iterator<char>(md)), std::istreambuf_iterator<char>());
  EXPECT_NE(table.find("runs without collision"), std::string::npos) << table;
  EXPECT_NE(table.find("set-offs more than 10 deg off"), std::string::npos) << table;
  std::filesystem::remove_all(out);
}

// `--calib FILE` (explore and eval explore): the defaults written as a file give the same run as no
// file; a file that changes the heading cues' weights changes the run; a bad file is one clear
// error line and no output folder.
TEST(ExploreCli, CalibrationFileIsReadBack) {
  const auto dir = TempDir("calib");
  std::filesystem::create_directories(dir);
  {
    std::ofstream(dir / "defaults.yaml") << "heading: {slice_width_px: 3}\n";
    std::ofstream(dir / "bright.yaml") << "heading:\n  cues:\n    bright: {weight: 4.0}\n    symmetry: {weight: 0.5}\n";
    std::ofstream(dir / "bad.yaml") << "heading:\n  cues:\n    bright: {weight: [1, 2]}\n";
  }
  auto summary = [&](const std::string& name, const std::string& calib) {
    const auto out = dir / name;
    const CliResult r = RunSquint("explore --world corridor-3 --minutes 0.4 --seed 4 --out " + out.string() + calib);
    EXPECT_EQ(r.code, 0) << r.all();
    std::ifstream js(out / "summary.json");
    return nlohmann::json::parse(js);
  };
  const nlohmann::json none = summary("none", "");
  const nlohmann::json defaults = summary("defaults", " --calib " + (dir / "defaults.yaml").string());
  const nlohmann::json bright = summary("bright", " --calib " + (dir / "bright.yaml").string());
  EXPECT_EQ(none["distance_m"], defaults["distance_m"]);
  EXPECT_EQ(none["frames_fully_processed"], defaults["frames_fully_processed"]);
  EXPECT_EQ(none["axis_error_p90_deg"], defaults["axis_error_p90_deg"]);
  EXPECT_NE(none["axis_error_p90_deg"], bright["axis_error_p90_deg"]);

  const auto out = dir / "bad-out";
  const CliResult r = RunSquint("eval explore --world corridor-3 --starts 1 --minutes 0.2 --calib " +
                                (dir / "bad.yaml").string() + " --out " + out.string());
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("bad.yaml"), std::string::npos) << r.all();
  EXPECT_FALSE(std::filesystem::exists(out));
  std::filesystem::remove_all(dir);
}

// `--obstacle-pipeline` runs the obstacle pipeline in the loop (its counts in summary.json); off by
// default.
TEST(ExploreCli, ObstaclePipelineSwitch) {
  const auto dir = TempDir("ipt");
  auto pairs = [&](const std::string& name, const std::string& flag) {
    const auto out = dir / name;
    const CliResult r = RunSquint("explore --world obstacle-course --minutes 0.3 --seed 2 --out " + out.string() + flag);
    EXPECT_EQ(r.code, 0) << r.all();
    std::ifstream js(out / "summary.json");
    return nlohmann::json::parse(js)["ipt_pairs"].get<long>();
  };
  EXPECT_EQ(pairs("off", ""), 0);
  EXPECT_GT(pairs("on", " --obstacle-pipeline"), 0);
  std::filesystem::remove_all(dir);
}

// Session 19's five rules, session 20's --blind-texture-keep-ref, session 21's --blocked-hold,
// session 22's two, session 23's two, session 26's --far-floor-diff, session 28's
// --setoff-blocked-min-range, session 29's --mirror-watch, session 30's --feel-contacts, session 31's
// --probe-wall-lines-memory and session 32's --setoff-near-edges, each switched off (and session 27's
// --blocked-min-range and --settled-blocked-min-range at their defaults), but for the one named
// (so a test of one replays its case as it was found, with the others as they were then);
// LaterRulesOffBut("") switches them all off. Session 39's three defaults are a list of their own,
// which Session39OffBut reads alone, and so are session 45's (kBeforeSession45) and session 49's
// (kBeforeSession49).
using Rules = std::vector<std::pair<std::string, std::string>>;  // a switch's name, its "off" flags

const Rules& Session49Rules() {
  static const Rules rules = {{"--wall-keep", " --wall-keep 0"},
                              {"--wall-keep-min", " --wall-keep-min 0"},
                              {"--scan-wall-entropy", " --scan-wall-entropy 0"},
                              {"--own-range-driving", " --no-own-range-driving"}};
  return rules;
}

const Rules& Session45Rules() {
  static const Rules rules = {{"--wall-line-align-over", " --wall-line-align-over 0"},
                              {"--scan-entropy-floor", " --scan-entropy-floor 0"},
                              {"--shift-trusts-points", " --shift-trusts-points 0"}};
  return rules;
}

const Rules& Session39Rules() {
  static const Rules rules = {{"--mouth-drop-strays", " --no-mouth-drop-strays"},
                              {"--blind-points-edge-keep", " --blind-points-edge-keep 0"},
                              {"--blind-points-edge-keep-driving-only", " --no-blind-points-edge-keep-driving-only"}};
  return rules;
}

const Rules& LaterRules() {
  static const Rules rules = [] {
    Rules r = {{"--side-wall-cluster", " --side-wall-cluster 0"},
                                                                  {"--floor-edge-band-mouth", " --no-floor-edge-band-mouth"},
                                                                  {"--blocked-hold-in-view", " --no-blocked-hold-in-view"},
                                                                  {"--blind-texture-keep-peak", " --no-blind-texture-keep-peak"},
                                                                  {"--blocked-hold", " --blocked-hold 0"},
                                                                  {"--blind-texture-keep-ref", " --no-blind-texture-keep-ref"},
                                                                  {"--blind-texture-start", " --blind-texture-start 0"},
                                                                  {"--scan-wall-lines", " --scan-wall-lines 0"},
                                                                  {"--wall-view-hold", " --wall-view-hold 0"},
                                                                  {"--shift-trusts-memory", " --no-shift-trusts-memory"},
                                                                  {"--wall-lines-hold", " --wall-lines-hold 0"},
                                                                  {"--probe-wall-lines", " --probe-wall-lines 0"},
                                                                  {"--probe-wall-lines-memory", " --no-probe-wall-lines-memory"},
                                                                  {"--far-floor-diff", " --far-floor-diff 0"},
                                                                  {"--far-floor-from", " --far-floor-from 0"},
                                                                  {"--blocked-min-range", " --blocked-min-range 0.6"},
                                                                  {"--settled-blocked-min-range", " --settled-blocked-min-range 0"},
                                                                  {"--setoff-blocked-min-range", " --setoff-blocked-min-range 0"},
                                                                  {"--setoff-near-edges", " --no-setoff-near-edges"},
                                                                  {"--mirror-watch", " --no-mirror-watch"},
                                                                  {"--feel-contacts", " --no-feel-contacts"}};
    r.insert(r.end(), Session39Rules().begin(), Session39Rules().end());
    r.insert(r.end(), Session45Rules().begin(), Session45Rules().end());
    r.insert(r.end(), Session49Rules().begin(), Session49Rules().end());
    return r;
  }();
  return rules;
}

// The "off" flags of the rules, but for the one named.
std::string RulesOffBut(const Rules& rules, const std::string& keep) {
  std::string flags;
  for (const auto& [name, off] : rules)
    if (name != keep) flags += off;
  return flags;
}

std::string LaterRulesOffBut(const std::string& keep) { return RulesOffBut(LaterRules(), keep); }

// Session 39's three defaults (--mouth-drop-strays, --blind-points-edge-keep 15 and
// --blind-points-edge-keep-driving-only) off, but for the one named.
std::string Session39OffBut(const std::string& keep) { return RulesOffBut(Session39Rules(), keep); }

// Session 49's four defaults (--wall-keep 0.45, --wall-keep-min 0.25, --scan-wall-entropy 0.7 and
// --own-range-driving) off: the explorer as it was before them. They avoid several of the failures
// below by another route.
const std::string kBeforeSession49 = RulesOffBut(Session49Rules(), "");

// Session 45's three defaults (--wall-line-align-over 25, --scan-entropy-floor 0.9 and
// --shift-trusts-points 1.2) off, and session 49's: the explorer as it was before them. They avoid
// several of the failures below by another route (mostly the walls' lines' axis at a set-off far
// off it).
const std::string kBeforeSession45 = RulesOffBut(Session45Rules(), "") + kBeforeSession49;

// All three off, and session 45's: the explorer as it was when the failures below were found, most
// of which these defaults avoid by another route.
const std::string kBeforeSession39 = Session39OffBut("") + kBeforeSession45;

// The explorer as it was before session 17 made the walls' lines and their companions the
// defaults (and without session 18's, 19's and 20's defaults).
const std::string kWithoutWallLines =
    " --no-wall-lines --no-end-probe-memory --no-wall-lines-binned --wall-line-free 0 --no-rearm-after-gap --no-mouth-wall-line"
    " --arrival-min-travel 0 --shift-stall 0 --no-blind-side-lines --blind-texture 0 --no-scan-blind-start --sonar-end-blocks 0" +
    LaterRulesOffBut("");

// --own-range-clearing (off by default), with the explorer as it was without the walls' lines
// (session 14): obstacle-course start 1 of seed 12 sets off beside the
// chair at (8.5, -1.2), whose 4 cm legs the sonar's median across columns votes out; the floor
// seen under its seat then clears the memory there and the robot touches the chair within 5 s.
// With each column clearing only up to its own reading the legs stay remembered: no contact.
TEST(ExploreCli, OwnRangeClearingKeepsTheChairLegsRemembered) {
  const auto dir = TempDir("own");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world obstacle-course --seed 12 --eval-start 1 --minutes 0.25" + flag);
  };
  // Without it: the first contact is the chair (the world file's obstacles[3]), within 5 s, with
  // the robot's centre within its reach (the seat spans 8.275-8.725 x -1.425 to -0.975 m).
  const nlohmann::json off = summary("off", kWithoutWallLines);
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "obstacles[3] (chair)");
  EXPECT_LT(off["first_collision_s"].get<double>(), 5.0);
  EXPECT_NEAR(off["first_collision_x_m"].get<double>(), 8.5, 0.225 + 0.22 + 0.01);
  EXPECT_NEAR(off["first_collision_y_m"].get<double>(), -1.2, 0.225 + 0.22 + 0.01);
  const nlohmann::json on = summary("on", kWithoutWallLines + " --own-range-clearing");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  EXPECT_TRUE(on["first_collision_s"].is_null());
  EXPECT_EQ(on["first_hit"].get<std::string>(), "");
  std::filesystem::remove_all(dir);
}

// corridor-2 (carpet under panels of its grey), seeded start 4 of seed 2: set off within 4° of
// the axis, the glance's scattered heading lets the axis wander (more than 10° off on 42 % of the
// following frames) and the robot meets a wall at 119 s. With the walls' lines (and the end probe
// that the exactly held axis needs at L corners) the axis stays within 10° on 97 % and it does not;
// so too with all of session 17's defaults. (With session 19's --blind-texture-start before its
// rule was spent at the first stall, the defaults held the robot on open floor at this start for a
// minute and then set it off 30° off the axis: 21 % of the frames more than 10° off.)
TEST(ExploreCli, WallLinesHoldTheAxisWhereTheWallsHaveTheFloorsGrey) {
  const auto dir = TempDir("wall-lines");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world corridor-2 --seed 2 --eval-start 4 --minutes 2.1" + flag);
  };
  const nlohmann::json off = summary("off", kWithoutWallLines);
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
  EXPECT_GT(off["axis_error_over_10deg"].get<double>(), 0.3);
  const nlohmann::json on = summary("on", kWithoutWallLines + " --wall-lines --end-probe-memory");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  EXPECT_LT(on["axis_error_over_10deg"].get<double>(), 0.1);
  const nlohmann::json defaults = summary("defaults", "");
  EXPECT_EQ(defaults["collisions"].get<long>(), 0);
  EXPECT_LT(defaults["axis_error_over_10deg"].get<double>(), 0.1);
  std::filesystem::remove_all(dir);
}

// A T met from its bar (world file): the robot must find the stem from the bar, turn into it
// (a -90 turn near x = 12) and cover more than the bar alone (24 of 34 m) in two minutes.
// corridor-1, seeded start 6 of seed 1: the robot starts inside the T's junction, 0.4 m from the
// cross corridor's east wall, and stops 0.4 m on. Recording the branch behind it (the east wall)
// as explored, the map later sends it there: it stalls against the wall, and the drive to the
// mouth's centre that follows pushes on against it for the drive's whole time limit (232 contacts
// by 102 s). Ending that drive when the wheels stop (--shift-stall) leaves the first stall's
// contacts only; recording the branch behind a stop as explored only when the robot came along
// it (--arrival-min-travel) keeps it off the wall.
TEST(ExploreCli, AStartInAJunctionLeavesTheBranchBehindUnknownAndAStalledShiftEnds) {
  const auto dir = TempDir("junction-start");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world corridor-1 --seed 1 --eval-start 6 --minutes 1.7 --blocked-min-range 0.6 --setoff-blocked-min-range 0" + kBeforeSession49 + flag);
  };
  // Session 21's --blocked-hold and session 30's --feel-contacts, off as when the case was found
  // (the first keeps the robot off the wall too, the second backs it off the wall at the first contact).
  const nlohmann::json before = summary("before", " --arrival-min-travel 0 --shift-stall 0 --blocked-hold 0 --no-feel-contacts");
  EXPECT_GT(before["collisions"].get<long>(), 150);
  EXPECT_EQ(before["first_hit"].get<std::string>(), "wall");
  const nlohmann::json shift_stall = summary("shift-stall", " --arrival-min-travel 0 --blocked-hold 0 --no-feel-contacts");
  EXPECT_GT(shift_stall["collisions"].get<long>(), 0);
  EXPECT_LT(shift_stall["collisions"].get<long>(), 80);
  const nlohmann::json defaults = summary("defaults", "");
  EXPECT_EQ(defaults["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// obstacle-course, seeded start 2 of seed 1: at 150 s the sonar reads an end with the bin at
// (9.5, 1.3) 0.48 m ahead, at a junction node whose branch ahead the map holds explored (the robot
// came that way earlier, beside the bin); the decision goes straight on and the robot meets the
// bin. With --sonar-end-blocks 1.0 that branch is a wall now and the robot turns.
TEST(ExploreCli, ASonarEndCloseAheadBlocksABranchTheMapHoldsExplored) {
  const auto dir = TempDir("sonar-end");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world obstacle-course --seed 1 --eval-start 2 --minutes 2.6 --far-floor-diff 0 --blocked-min-range 0.6 --setoff-blocked-min-range 0" + kBeforeSession45 + flag);  // as found: before session 26's far-floor rule and sessions 27-28's sectors
  };
  // Session 21's --blocked-hold, off as when the case was found (it keeps the robot off the bin too).
  const nlohmann::json off = summary("off", " --sonar-end-blocks 0 --blind-texture 0 --no-scan-blind-start --blocked-hold 0");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "obstacles[4] (bin)");
  const nlohmann::json on = summary("on", " --sonar-end-blocks 1.0 --blind-texture 0 --no-scan-blind-start --blocked-hold 0");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// default, seeded start 8 of seed 8: 0.47 m from the north corridor's wall, facing it 18° off
// its normal; a door frame in view gives the glance a corridor's entropy and a steady heading,
// and every sonar column is blocked near (read as unknown: a blind view). Taken for a corridor,
// the robot sets off into the wall within 1.1 s. With --scan-blind-start it looks all around first.
TEST(ExploreCli, ABlindStartViewIsScannedFirst) {
  const auto dir = TempDir("blind-start");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--seed 8 --eval-start 8 --minutes 0.5" + flag);
  };
  // Session 21's --blocked-hold, off as when the case was found (it keeps the robot off the wall too).
  const nlohmann::json off = summary("off", " --no-scan-blind-start --blocked-hold 0");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_LT(off["first_collision_s"].get<double>(), 2.0);
  const nlohmann::json on = summary("on", " --scan-blind-start --blocked-hold 0");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// corridor-2 (panels of the carpet's grey), seeded start 2 ("close to a wall") of seed 15: 0.35 m
// from the turn corridor's east wall, heading 13° into it while the glance reads 6°. Every sonar
// column is blocked near and read as unknown (a blind view); the robot meets the wall within 2 s.
// With --blind-texture the columns whose bottom in the walls' lines' frame is smooth (the wall)
// stay blocked near.
TEST(ExploreCli, BlindTextureKeepsAWallOfTheFloorsGreyBlocked) {
  const auto dir = TempDir("blind-texture");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world corridor-2 --seed 15 --eval-start 2 --minutes 0.3" + flag);
  };
  const nlohmann::json off = summary("off", " --blind-texture 0 --no-scan-blind-start");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_LT(off["first_collision_s"].get<double>(), 3.0);
  const nlohmann::json on = summary("on", " --blind-texture 0.35 --no-scan-blind-start");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// corridor-2, seeded start 2 ("close to a wall") of seed 6: 0.3 m from the turn corridor's east
// wall, heading 10° into it. The wall's panels have the carpet's grey, so the sonar reads its
// columns unknown without a blind view (the far wall and the floor are read), and the robot meets
// the wall within 4 s. With --blind-texture-start the smooth-bottom rule applies to those unknown
// columns over the first 2 m from the start, and they stay blocked near.
TEST(ExploreCli, BlindTextureStartKeepsACloseStartOffAWallOfTheFloorsGrey) {
  const auto dir = TempDir("blind-texture-start");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world corridor-2 --seed 6 --eval-start 2 --minutes 0.3" + LaterRulesOffBut("--blind-texture-start") + flag);
  };
  const nlohmann::json off = summary("off", " --blind-texture-start 0");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_LT(off["first_collision_s"].get<double>(), 4.0);
  const nlohmann::json on = summary("on", " --blind-texture-start 2");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// corridor-9, seeded start 7 of seed 14: 0.65 m from the main corridor's brick side wall, facing
// it. Up close the sonar reads the mortar as floor running far (no column blocked), so the
// start-up scan finds the wall's direction the freest and sets off into it (contact at 13.6 s).
// With --scan-wall-lines the scan's views with the brick's lines across the frame are wall views,
// and it sets off down the corridor.
TEST(ExploreCli, AScanDoesNotSetOffIntoABrickWallUpClose) {
  const auto dir = TempDir("scan-wall-lines");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world corridor-9 --seed 14 --eval-start 7 --minutes 0.3" + LaterRulesOffBut("--scan-wall-lines") + flag);
  };
  const nlohmann::json off = summary("off", " --scan-wall-lines 0");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_LT(off["first_collision_s"].get<double>(), 15.0);
  const nlohmann::json on = summary("on", " --scan-wall-lines 0.75");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// The obstacle course, seeded start 3 of seed 5: boxed in among the boxes, the robot faces the
// rotated box 0.4 m ahead (nearly every sonar column blocked near) after a full turn; the glance's
// entropy hovers at the blind-view threshold, one frame above it reads the view blind (its
// columns unknown), and the robot drives into the box at 170.5 s. With --wall-view-hold a blind
// view taken within 0.1 m and 10 degrees of the last wall view is a wall.
TEST(ExploreCli, AWallViewHeldKeepsTheRobotOffABoxUpClose) {
  const auto dir = TempDir("wall-view-hold");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world obstacle-course --seed 5 --eval-start 3 --minutes 2.9" + LaterRulesOffBut("--wall-view-hold") + flag);
  };
  const nlohmann::json off = summary("off", " --wall-view-hold 0");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  const nlohmann::json on = summary("on", " --wall-view-hold 0.1");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// corridor-8, seeded start 4 of seed 5: stopped 1.1 m short of the cross corridor's centre, the
// drive along the axis to the mouth's centre is held by the tiles' joints read blocked near until
// its time limit; the robot turns north from there, on the branch's wall line, and meets the
// corner at 48 s. With --shift-trusts-memory the drive takes the floor seen on the way in as
// free, reaches the centre and turns there.
TEST(ExploreCli, TheDriveToAMouthsCentreTrustsTheFloorSeenOnTheWayIn) {
  const auto dir = TempDir("shift-trusts-memory");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world corridor-8 --seed 5 --eval-start 4 --minutes 0.9" + LaterRulesOffBut("--shift-trusts-memory") + flag);
  };
  const nlohmann::json off = summary("off", " --no-shift-trusts-memory");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  const nlohmann::json on = summary("on", " --shift-trusts-memory");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// corridor-9, seeded start 9 of seed 14: turned north into the cross corridor a metre short of its
// centre, the robot heads for the corner of the main corridor's brick wall. The sonar reads the
// brick's columns blocked near, but the floor there was "seen" from farther back (the mortar read
// as floor), and the brick's lines, which revoke that, show on only half of the frames as the
// corner leaves the view: contact at 98.4 s. With --wall-lines-hold 1 the lines seen within the
// last second count, and the robot stops short of the corner.
TEST(ExploreCli, BrickLinesHeldOverASecondKeepTheRobotOffABrickCorner) {
  const auto dir = TempDir("wall-lines-hold");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world corridor-9 --seed 14 --eval-start 9 --minutes 1.7" + LaterRulesOffBut("--wall-lines-hold") + flag);
  };
  const nlohmann::json off = summary("off", " --wall-lines-hold 0");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  const nlohmann::json on = summary("on", " --wall-lines-hold 1");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// corridor-5 (a mirror at its east end), seeded start 2 of seed 6: on its second visit to the
// mirror the robot weaves toward it 20° off the axis at full speed (the mirror shows the corridor
// behind, the sonar reads floor running on, the fused distance 4-6 m) and its disc meets the end
// wall at 152.6 s, before the end is detected. The map holds that end a dead end since the first
// visit; with --known-end-slow 3 the robot creeps over the last metres to it and stops clear.
// (--far-floor-from 0 as before session 36: with its default of 2 this run meets nothing either way.)
TEST(ExploreCli, TheRobotCreepsTowardAPlaceTheMapHoldsADeadEnd) {
  const auto dir = TempDir("known-end-slow");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world corridor-5 --seed 6 --eval-start 2 --minutes 3 --blocked-hold 0 --blocked-min-range 0.6 --setoff-blocked-min-range 0 --no-mirror-watch --far-floor-from 0" + kBeforeSession49 + flag);
  };
  const nlohmann::json off = summary("off", " --known-end-slow 0");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
  EXPECT_GT(off["first_collision_x_m"].get<double>(), 25.0);  // at the mirror end (the east one)
  const nlohmann::json on = summary("on", " --known-end-slow 3");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  EXPECT_GE(on["ends_detected"].get<long>(), 3);  // both ends, and the mirror again
  // Creeping only where the fused distance reads the end more than 1.5 m beyond the map's: the
  // mirror shows the corridor behind, so the robot still creeps to it.
  const nlohmann::json disagree = summary("disagree", " --known-end-slow 3 --known-end-disagree 1.5");
  EXPECT_EQ(disagree["collisions"].get<long>(), 0);
  EXPECT_GE(disagree["ends_detected"].get<long>(), 3);
  std::filesystem::remove_all(dir);
}

// corridor-5, seeded start 0 of seed 23: the mirror end met on the second visit as above (154.5 s,
// 24° off the axis), with the defaults. Nearing the mirror the robot sees its own reflection, and
// the sonar reads that reflection's base as a thing standing 1.4 m ahead; steering around it, the
// robot turned toward the mirror's reflected corridor beside it. With --mirror-watch the
// reflection, coming nearer at twice the robot's speed, gives the mirror away and a wall is
// remembered on its plane: the robot stops clear of it on every visit. Start 2 of seed 6 with the
// settings it failed with (the test above) meets nothing either. (--far-floor-from 0 as before
// session 36: with its default of 2 the run without --mirror-watch meets nothing either.)
TEST(ExploreCli, TheRobotKnowsAMirrorByItsOwnReflection) {
  const auto dir = TempDir("mirror-watch");
  const std::string start = "--world corridor-5 --seed 23 --eval-start 0 --minutes 2.7 --far-floor-from 0" + kBeforeSession49;
  const nlohmann::json off = ExploreSummary(dir / "off", start + " --no-mirror-watch");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
  EXPECT_GT(off["first_collision_x_m"].get<double>(), 25.0);  // at the mirror end (the east one)
  EXPECT_EQ(off["mirror_scans"].get<long>(), 0);
  const nlohmann::json on = ExploreSummary(dir / "on", start + " --mirror-watch");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  EXPECT_GT(on["mirror_scans"].get<long>(), 0);
  EXPECT_GE(on["ends_detected"].get<long>(), 3);  // both ends, and the mirror again
  const nlohmann::json old = ExploreSummary(
      dir / "seed-6", "--world corridor-5 --seed 6 --eval-start 2 --minutes 3 --blocked-hold 0 --blocked-min-range 0.6 "
                      "--setoff-blocked-min-range 0 --far-floor-from 0 --mirror-watch");
  EXPECT_EQ(old["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// The obstacle course, seeded start 5 of seed 7: started between the rotated box and the south
// wall, the robot meets the box's corner with its flank at 93.1 s, beside the camera's view and
// inside the sonar's blind range. Without --feel-contacts it sets off into the corner after every
// scan (33 simulator steps in contact by 2 minutes); with it the wheels' missing progress is a
// contact, remembered ahead of the disc, and the robot reverses and goes elsewhere: two steps in
// contact, the one contact felt. (--far-floor-from 0 as before session 36: with its default of 2
// the robot meets nothing on this start, with or without --feel-contacts.)
TEST(ExploreCli, AContactFeltFromTheWheelsIsNotPushedIntoAgain) {
  const auto dir = TempDir("feel-contacts");
  const std::string start = "--world obstacle-course --seed 7 --eval-start 5 --minutes 2 --far-floor-from 0" + kBeforeSession39;
  const nlohmann::json off = ExploreSummary(dir / "off", start + " --no-feel-contacts");
  EXPECT_GT(off["collisions"].get<long>(), 20);
  EXPECT_EQ(off["contacts_felt"].get<long>(), 0);
  const nlohmann::json on = ExploreSummary(dir / "on", start + " --feel-contacts");
  EXPECT_GE(on["contacts_felt"].get<long>(), 1);
  EXPECT_LE(on["collisions"].get<long>(), 2 * on["contacts_felt"].get<long>());
  EXPECT_NEAR(on["first_collision_s"].get<double>(), off["first_collision_s"].get<double>(), 1e-9);  // the same first contact
  std::filesystem::remove_all(dir);
}

// corridor-9 (brick walls, carpet; the camera sees no floor nearer than 1.28 m), seeded start 7
// of seed 38: the robot takes an end 2.2 m before the T and probes with the brick side wall 0.68 m
// away. Its scan shows the mortar lines in every band (so the sonar's free travel does not open
// that side, --probe-wall-lines) and an entropy at the open threshold, and the memory holds
// nothing there (the wall is inside the blind range), so --end-probe-memory opened it and the
// robot turned into the wall at 40.7 s. With --probe-wall-lines-memory (the default since session
// 31) the lines keep the memory from opening it: the robot turns around and meets nothing.
TEST(ExploreCli, BrickLinesKeepTheMemoryFromOpeningAWallAtAnEnd) {
  const auto dir = TempDir("probe-wall-lines-memory");
  const std::string start = "--world corridor-9 --seed 38 --eval-start 7 --minutes 1";
  const nlohmann::json off = ExploreSummary(dir / "off", start + " --no-probe-wall-lines-memory");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
  const nlohmann::json on = ExploreSummary(dir / "on", start);
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  EXPECT_EQ(on["first_hit"].get<std::string>(), "");
  std::filesystem::remove_all(dir);
}

// corridor-9, seeded start 2 of seed 35: a start "close to a wall", 0.35 m east of the convex
// corner where the main corridor meets the cross corridor (1.28 m of floor hidden below that
// camera's view). The scan sets the robot off west with the corner 11 degrees to its left. The
// corner's painted face has the tiles' grey: the sonar knows something stands there, not how near.
// The robot turned away from it and met it with its flank at 13.6 s. With --setoff-near-edges (the
// default since session 32) the face's edge, ranged by the first 5 cm of travel at about 0.27 m,
// is remembered: the robot stops there, backs off, scans again, sets off the other way and meets
// nothing.
TEST(ExploreCli, ACornerRangedByTheTravelsParallaxIsNotMetSettingOff) {
  const auto dir = TempDir("setoff-near-edges");
  const std::string start = "--world corridor-9 --seed 35 --eval-start 2 --minutes 1" + kBeforeSession39;
  const nlohmann::json off = ExploreSummary(dir / "off", start + " --no-setoff-near-edges");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
  EXPECT_LT(off["first_collision_s"].get<double>(), 15.0);
  EXPECT_EQ(off["near_edges"].get<long>(), 0);
  const nlohmann::json on = ExploreSummary(dir / "on", start);
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  EXPECT_EQ(on["first_hit"].get<std::string>(), "");
  EXPECT_GT(on["near_edges"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// corridor-9, seeded start 2 of seed 45: the same convex corner, 0.35 m from the robot, which sets
// off west with the corner 28 degrees to its left, at the edge of its view. Blocked-near columns
// on either side close every heading; then its right-hand ones clear, the robot turns right toward
// a heading the corner's columns leave free, and its view loses the corner at once: the latest
// scan shows nothing near, the held columns counted only in the view, and at 39 degrees off the
// heading it drove off into the corner (first contact 15.3 s). With --setoff-standing-hold 0.02
// (off by default) the corner's columns, an edge (floor running far beside them), held where it
// stands count out of the view too: no heading is free, the stall guard gives the direction up,
// the probe turns the robot into the cross corridor, and it meets nothing.
TEST(ExploreCli, ACornerThatLeftTheViewStillHoldsWhereTheRobotStands) {
  const auto dir = TempDir("setoff-standing-hold");
  const std::string start = "--world corridor-9 --seed 45 --eval-start 2 --minutes 0.5" + kBeforeSession39;
  const nlohmann::json off = ExploreSummary(dir / "off", start);  // the default: off
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
  EXPECT_LT(off["first_collision_s"].get<double>(), 16.0);
  const nlohmann::json on = ExploreSummary(dir / "on", start + " --setoff-standing-hold 0.02");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  EXPECT_EQ(on["first_hit"].get<std::string>(), "");
  std::filesystem::remove_all(dir);
}

// The obstacle course, seeded start 5 of seed 59: after a probe the robot faces west with the dark
// bin (0.45 m tall, the camera 0.43 m high) 0.5 m ahead, inside the blind range. The bin fills its
// sonar columns from the bottom row to its top edge just above the horizon, so their only step was
// that edge, at the horizon: floor running 6 m on. Those "far" columns cleared what the memory held
// of the bin, and the robot met it with its flank at 38.8 s. With --far-floor-diff 40 a far column
// whose bottom rows are unlike the frame's floor is blocked near: the probe finds no way west, the
// robot scans instead and meets nothing.
TEST(ExploreCli, ADarkBinFillingTheViewToTheHorizonIsNoFloorRunningOn) {
  const auto dir = TempDir("far-floor-diff");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world obstacle-course --seed 59 --eval-start 5 --minutes 0.7 --blocked-min-range 0.6 --setoff-blocked-min-range 0" + kBeforeSession49 + flag);
  };
  const nlohmann::json off = summary("off", " --far-floor-diff 0");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "obstacles[4] (bin)");
  const nlohmann::json on = summary("on", "");  // the default since session 26
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  EXPECT_EQ(on["first_hit"].get<std::string>(), "");
  std::filesystem::remove_all(dir);
}

// The default building, seeded start 7 of seed 70 (session 34, a seed no rule was tuned on): the
// robot sets off with the bin (0.45 m tall under a 0.6 m camera) 15° to its left, its near side
// 0.73 m away. The bin's dark face fills its sonar columns from the bottom row up to its top edge,
// which lies below the horizon at a floor range of about 2.9 m: a boundary in range, so
// --far-floor-diff (far steps only) read floor running 2.9 m there, the memory held nothing of
// the bin, and the robot met it with its flank at 3.3 s (as it still does with --far-floor-from 0).
// With --far-floor-from 2 (the default since session 36) those columns are blocked near and it
// meets nothing.
TEST(ExploreCli, ABinALittleLowerThanTheCameraIsNoFloorRunningOnWithFarFloorFrom) {
  const auto dir = TempDir("far-floor-from");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world default --seed 70 --eval-start 7 --minutes 0.15" + flag);
  };
  const nlohmann::json far_only = summary("far-only", " --far-floor-from 0");
  EXPECT_GT(far_only["collisions"].get<long>(), 0);
  EXPECT_EQ(far_only["first_hit"].get<std::string>(), "obstacles[0] (bin)");
  const nlohmann::json on = summary("on", "");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  EXPECT_EQ(on["first_hit"].get<std::string>(), "");
  std::filesystem::remove_all(dir);
}

// corridor-7, seeded start 4 of seed 98 (session 36, a seed no rule was tuned on): the robot
// starts in the L corner's square, 0.76 m from the convex corner where the main corridor's south
// wall meets the turn's west wall, and looks all around. The corner, inside the camera's blind
// range, is a run of blocked-near columns ending in floor running far (the turn corridor): soft
// points along those rays. Seen in the first half of the turn, they were forgotten after 5 s,
// before the set-off at 13.6 s, and the robot swung toward the turn and met the corner at 16.2 s
// (the defaults before session 39). Kept 15 s as a near thing's edge (--blind-points-edge-keep 15),
// they close that heading and the robot meets nothing, also when the kept points serve driving
// only (--blind-points-edge-keep-driving-only: the set-off's direction and the guard see them),
// as they do with the defaults since session 39; and with session 45's (which, with session 39's
// off, meet nothing here either).
TEST(ExploreCli, ACornerSeenDuringTheLookAroundIsStillKnownAtTheSetOff) {
  const auto dir = TempDir("blind-points-edge-keep");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world corridor-7 --seed 98 --eval-start 4 --minutes 0.35" + flag);
  };
  const nlohmann::json forgotten = summary("forgotten", kBeforeSession39);
  EXPECT_GT(forgotten["collisions"].get<long>(), 0);
  EXPECT_EQ(forgotten["first_hit"].get<std::string>(), "wall");
  EXPECT_NEAR(forgotten["first_collision_x_m"].get<double>(), 39.1, 0.25 + 0.15);
  EXPECT_NEAR(forgotten["first_collision_y_m"].get<double>(), -0.9, 0.25 + 0.15);
  const nlohmann::json kept = summary("kept", Session39OffBut("--blind-points-edge-keep") + " --blind-points-edge-keep 15" + kBeforeSession45);
  EXPECT_EQ(kept["collisions"].get<long>(), 0);
  EXPECT_EQ(kept["first_hit"].get<std::string>(), "");
  const nlohmann::json driving = summary("driving", kBeforeSession45);  // the defaults of sessions 39-44
  EXPECT_EQ(driving["collisions"].get<long>(), 0);
  EXPECT_EQ(driving["first_hit"].get<std::string>(), "");
  const nlohmann::json defaults = summary("defaults", "");  // the defaults since session 45
  EXPECT_EQ(defaults["collisions"].get<long>(), 0);
  EXPECT_EQ(defaults["first_hit"].get<std::string>(), "");
  std::filesystem::remove_all(dir);
}

// corridor-8, seeded start 3 of seed 108 (session 37, a fresh seed): the robot stops for the cross
// corridor's south opening as its right wall ends, 1 m short of the cross's centre line, and turns
// into the north branch. One stray remembered point inside the mouth splits it, mouth centring
// finds no centre, and the robot drives north 1 m off the branch's centre line and meets its near
// corner at 79.8 s (the defaults before session 39). With --mouth-drop-strays it first moves
// 0.78 m along to the centre line and meets nothing, as it does with the defaults since session 39.
TEST(ExploreCli, AStrayPointInsideAMouthDoesNotKeepTheRobotOffItsCentre) {
  const auto dir = TempDir("mouth-drop-strays");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world corridor-8 --seed 108 --eval-start 3 --minutes 1.4" + flag);
  };
  const nlohmann::json off = summary("off", kBeforeSession39);
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
  EXPECT_NEAR(off["first_collision_x_m"].get<double>(), 12.9, 0.25 + 0.1);
  EXPECT_NEAR(off["first_collision_y_m"].get<double>(), 1.4, 0.25 + 0.1);
  const nlohmann::json on = summary("on", Session39OffBut("--mouth-drop-strays") + " --mouth-drop-strays");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  EXPECT_EQ(on["first_hit"].get<std::string>(), "");
  const nlohmann::json defaults = summary("defaults", "");
  EXPECT_EQ(defaults["collisions"].get<long>(), 0);
  EXPECT_EQ(defaults["first_hit"].get<std::string>(), "");
  std::filesystem::remove_all(dir);
}

// Two starts inside the camera's blind range of something standing, whose distance a blocked-near
// sonar column does not tell. The obstacle course, start 1 of seed 4: after a full turn the robot
// stood 0.36 m from the concrete column at (7.0, 0.6); its columns blocked near closed a sector of
// ±32° about them (a thing 0.6 m away assumed), the robot set off along the sector's edge and met
// the column with its flank at 30.1 s. corridor-9, start 2 of seed 17: set off 0.38 m from a convex
// corner and met the wall at 15.8 s (both with 0.6 m, the default, no set-off range, and session
// 39's defaults off: with them the corner's start meets nothing even so). With the
// sector for a thing 0.45 m away (--blocked-min-range 0.45; ±45° for the obstacle course's disc)
// neither meets anything.
const std::string kColumnStart = "--world obstacle-course --seed 4 --eval-start 1 --minutes 0.6";
const std::string kCornerStart = "--world corridor-9 --seed 17 --eval-start 2 --minutes 0.35";

TEST(ExploreCli, SomethingInsideTheBlindRangeMayStandNearerThanTheSectorAssumed) {
  const auto dir = TempDir("blocked-min-range");
  const nlohmann::json column_off = ExploreSummary(dir / "column-off", kColumnStart + " --blocked-min-range 0.6 --setoff-blocked-min-range 0" + kBeforeSession39);
  EXPECT_GT(column_off["collisions"].get<long>(), 0);
  EXPECT_EQ(column_off["first_hit"].get<std::string>(), "obstacles[2] (column)");
  const nlohmann::json column_on = ExploreSummary(dir / "column-on", kColumnStart + " --blocked-min-range 0.45 --setoff-blocked-min-range 0");
  EXPECT_EQ(column_on["collisions"].get<long>(), 0);
  const nlohmann::json corner_off = ExploreSummary(dir / "corner-off", kCornerStart + " --blocked-min-range 0.6 --setoff-blocked-min-range 0" + kBeforeSession39);
  EXPECT_GT(corner_off["collisions"].get<long>(), 0);
  EXPECT_EQ(corner_off["first_hit"].get<std::string>(), "wall");
  const nlohmann::json corner_on = ExploreSummary(dir / "corner-on", kCornerStart + " --blocked-min-range 0.45 --setoff-blocked-min-range 0");
  EXPECT_EQ(corner_on["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// The same two starts with the 0.45 m sector only while setting off (from the start or a recovery
// scan until 1.6 m of following or the first turn; the defaults since session 28): both meet
// nothing, and seed 12's following of the carpeted middle corridor, which the nearer sector
// everywhere drove into its wall (next test), keeps the 0.6 m sector and meets nothing in those
// ten minutes either.
TEST(ExploreCli, TheNearerSectorWhileSettingOffOnly) {
  const auto dir = TempDir("setoff-blocked-min-range");
  const std::string setoff = " --blocked-min-range 0.6 --setoff-blocked-min-range 0.45";
  const nlohmann::json column = ExploreSummary(dir / "column", kColumnStart + setoff);
  EXPECT_EQ(column["collisions"].get<long>(), 0);
  const nlohmann::json corner = ExploreSummary(dir / "corner", kCornerStart + setoff);
  EXPECT_EQ(corner["collisions"].get<long>(), 0);
  const nlohmann::json carpet = ExploreSummary(dir / "carpet", "--seed 12 --minutes 10.2" + setoff);
  EXPECT_EQ(carpet["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// `default`, seed 12, the main job's 45 minutes with --blocked-min-range 0.45 everywhere:
// following the carpeted middle corridor east (its walls of the carpet's grey, no sonar boundary),
// the candidate headings more than 45 degrees off the axis take the wider sector, the robot turned
// 35 degrees off the axis and met the corridor's south wall at 605.6 s. With
// --settled-blocked-min-range 0.6 (the 0.6 m sector once following has come 1.6 m along a
// corridor) it meets nothing in those ten minutes. (Off by default: seed 2's 45 minutes then
// shuttle in one place; docs/explore.md, session 27.) With --far-floor-from 0, as before session
// 36: with its default of 2 the run without the switch drives another route and meets nothing.
TEST(ExploreCli, TheNearerSectorIsForSettingOffNotForFollowingACorridor) {
  const auto dir = TempDir("settled-blocked-min-range");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--seed 12 --minutes 10.2 --blocked-min-range 0.45 --far-floor-from 0" + kBeforeSession45 + flag);
  };
  const nlohmann::json off = summary("off", " --settled-blocked-min-range 0");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
  EXPECT_NEAR(off["first_collision_y_m"].get<double>(), 12.5 - 1.2 + 0.25, 0.02);  // the middle corridor's south wall
  const nlohmann::json on = summary("on", " --settled-blocked-min-range 0.6");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// corridor-6 (tiles, plain painted walls and doors), seeded start 4 of seed 12: a door read as a
// side branch, the robot turns into it. From 1 m the door fills the view, no floor below it: every
// sonar column blocked near, the glance's entropy at the blind-view threshold, so the view is
// read blind. The door's bottom then became the floor's texture reference itself, no column read
// smooth, and the robot drove on into the door (79.2 s). With --blind-texture-keep-ref the tiles'
// reference is kept, the door's columns stay blocked near and the robot stops.
TEST(ExploreCli, APlainDoorFillingTheViewIsNotTakenForTheFloor) {
  const auto dir = TempDir("blind-texture-keep-ref");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world corridor-6 --seed 12 --eval-start 4 --minutes 1.5 --blocked-hold 0" + kBeforeSession49 + flag);
  };
  const nlohmann::json off = summary("off", " --no-blind-texture-keep-ref");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
  EXPECT_LT(off["first_collision_y_m"].get<double>(), -0.8);  // in the door on the south side
  const nlohmann::json on = summary("on", " --blind-texture-keep-ref");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// corridor-0, seeded start 2 of seed 8: a door taken for a side branch (the sonar's wall run broken
// by its base); the robot turns into it at 85.3 s and, 1 m from it, the door fills the view (no
// floor below it, every sonar column blocked near, the glance's entropy at the blind-view
// threshold). Turning toward it, each frame a little smoother than the last had walked the floor's
// texture reference down from the tiles' 39 grey levels to the door's 2.7, so no column read smooth,
// the blind views' columns were unknown and the robot met the door at 87.7 s. With
// --blind-texture-keep-peak a view is judged against the largest reference of the last 10 s: the
// door's columns stay blocked near, the robot stops and turns away. (Session 23's rules are off:
// with --side-wall-cluster the door is no longer taken for a side branch on this start.)
TEST(ExploreCli, SmootherAndSmootherViewsOfADoorKeepTheFloorsTexture) {
  const auto dir = TempDir("blind-texture-keep-peak");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world corridor-0 --seed 8 --eval-start 2 --minutes 1.6 --no-blocked-hold-in-view"
                                            " --side-wall-cluster 0 --blocked-min-range 0.6 --setoff-blocked-min-range 0 --no-floor-edge-band-mouth" + kBeforeSession49 + flag);
  };
  const nlohmann::json off = summary("off", " --no-blind-texture-keep-peak");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
  EXPECT_GT(off["first_collision_y_m"].get<double>(), 0.7);  // in the door on the north side
  EXPECT_NEAR(off["first_collision_x_m"].get<double>(), 16.4, 0.5);
  const nlohmann::json on = summary("on", " --blind-texture-keep-peak");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// corridor-9, seeded start 5 of seed 3: the robot stops for the T at the corridor's end 1 m short
// of the bar's centre line (x = 24.05; the bar spans x = 24 to 26), the carpet meeting the bar's
// tiles there, and turns left into the bar. The floor-edge band cleared as it turns in was centred
// on the stop and reached 1.8 m back along the corridor, over the end of its own north wall (whose
// base the sonar reads a little beyond the wall line, inside the band): the wall's end went from
// the memory and the robot met the corner (24, 1) at 34.9 s. With --floor-edge-band-mouth the band
// spans only the opening: the corner stays remembered and the robot steers clear of it.
TEST(ExploreCli, AFloorEdgeBandSpanningOnlyTheMouthKeepsTheCorridorsCorner) {
  const auto dir = TempDir("floor-edge-band-mouth");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world corridor-9 --seed 3 --eval-start 5 --minutes 0.7 --far-floor-diff 0" + flag);  // as found: before session 26's far-floor rule
  };
  const nlohmann::json off = summary("off", " --no-floor-edge-band-mouth");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
  EXPECT_NEAR(off["first_collision_x_m"].get<double>(), 24.2, 0.3);
  EXPECT_NEAR(off["first_collision_y_m"].get<double>(), 0.9, 0.3);
  const nlohmann::json on = summary("on", " --floor-edge-band-mouth");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// obstacle-course, seeded start 5 of seed 59: the robot turns west 0.67 m short of the bin (9.5, 1.3)
// with the bin nearly dead ahead, inside the camera's 0.6 m blind range; it steers left round it,
// the bin leaves the view on its right, and steering back toward the axis it meets the bin with its
// right flank at 38.8 s. --guard-unknown 0.2 does not stop that flank: it holds the robot still only
// right after the start-up scan (the floor beside a robot that has not moved was never seen), and
// with --guard-unknown-after 0.5 (the guard only after 0.5 m of wheel travel) the run is the
// defaults' to the metre, the bin met at 38.8 s: the cells beside the path there were all marked
// known free. With the guard from the start the robot sets off later and takes another route, which
// happens to miss the bin (docs/explore.md, session 25).
TEST(ExploreCli, TheUnknownFloorGuardActsOnlyAtTheStartOnTheBinsFlankContact) {
  const auto dir = TempDir("guard-unknown");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world obstacle-course --seed 59 --eval-start 5 --minutes 0.7 --far-floor-diff 0 --blocked-min-range 0.6 --setoff-blocked-min-range 0" + kBeforeSession49 + flag);  // as found: before session 26's far-floor rule and sessions 27-28's sectors
  };
  const nlohmann::json off = summary("off", " --guard-unknown 0");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "obstacles[4] (bin)");
  EXPECT_NEAR(off["first_collision_s"].get<double>(), 38.8, 1.0);
  const nlohmann::json later = summary("later", " --guard-unknown 0.2 --guard-unknown-after 0.5");
  EXPECT_EQ(later["first_hit"].get<std::string>(), "obstacles[4] (bin)");
  EXPECT_EQ(later["first_collision_s"].get<double>(), off["first_collision_s"].get<double>());
  EXPECT_EQ(later["distance_m"].get<double>(), off["distance_m"].get<double>());
  const nlohmann::json on = summary("on", " --guard-unknown 0.2");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  EXPECT_NE(on["distance_m"].get<double>(), off["distance_m"].get<double>());
  std::filesystem::remove_all(dir);
}

// default, seeded start 2 of seed 12: started 0.35 m from the west corridor's brick east wall,
// heading down the corridor. The disc cannot pass the wall, so the robot turns away from it; the
// wall's blocked-near columns, held for half a second (--blocked-hold), kept it in place after the
// wall had left the view, the stall guard gave the direction up three times, and the fourth scan,
// its reference entropy taken from the wall, set it off into the brick at 59.2 s. With
// --blocked-hold-in-view a held column counts only while the latest frame looks along it: the
// robot gets clear of the wall and sets off down the corridor.
TEST(ExploreCli, HeldColumnsThatLeftTheViewLetTheRobotTurnAwayFromAWall) {
  const auto dir = TempDir("blocked-hold-in-view");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world default --seed 12 --eval-start 2 --minutes 1.1 --blocked-min-range 0.6 --setoff-blocked-min-range 0" + kBeforeSession45 + flag);
  };
  const nlohmann::json off = summary("off", " --no-blocked-hold-in-view");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
  EXPECT_GT(off["first_collision_x_m"].get<double>(), 0.7);  // the west corridor's east wall (x = 1)
  const nlohmann::json on = summary("on", " --blocked-hold-in-view");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  EXPECT_GT(on["distance_m"].get<double>(), 5.0);  // it got going
  std::filesystem::remove_all(dir);
}

// The obstacle course, seeded start 1 of seed 24: set off toward the chair at (13.5, 1.1), whose
// seat the sonar does not see (it is at the camera's height) and whose 4 cm legs it reads blocked
// near in one frame and as a boundary beyond the seat's shadow in the next; the speed limit follows
// the latest frame, so the robot creeps on in the frames between and meets the seat at 5.7 s.
// With --blocked-hold 0.5 the blocked-near columns of the last half second hold it back: no
// progress, it backs off and turns away.
// default, seeded start 2 of seed 17: started 0.35 m from the west corridor's brick east wall. At
// an end read 7 m short, the robot probes left, facing that wall 0.6 m away: the sonar reads the
// lit brick as floor and its mortar lines as far boundaries (3 m free), the glance's entropy is
// 0.71 of the reference (just above the 0.7 a wall's look must stay under), and the robot turns
// into the wall at 35.9 s. The probe scan shows a brick wall's lines in all its bands; with
// --probe-wall-lines (on by default) such a side is not open by the sonar.
TEST(ExploreCli, ABrickWallsLinesInTheProbeScanKeepTheSideClosed) {
  const auto dir = TempDir("probe-wall-lines");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world default --seed 17 --eval-start 2 --minutes 0.7 --blocked-min-range 0.6 --setoff-blocked-min-range 0" + flag);
  };
  const nlohmann::json off = summary("off", " --probe-wall-lines 0");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
  EXPECT_NEAR(off["first_collision_s"].get<double>(), 35.9, 1.0);
  EXPECT_GT(off["first_collision_x_m"].get<double>(), 0.7);  // the west corridor's east wall (x = 1)
  const nlohmann::json on = summary("on", "");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

TEST(ExploreCli, BlockedNearColumnsHeldKeepTheRobotOffAChair) {
  const auto dir = TempDir("blocked-hold");
  auto summary = [&](const std::string& name, const std::string& flag) {
    return ExploreSummary(dir / name, "--world obstacle-course --seed 24 --eval-start 1 --minutes 0.25 --far-floor-diff 0 --blocked-min-range 0.6 --setoff-blocked-min-range 0" + kBeforeSession49 + flag);  // as found: before session 26's far-floor rule and sessions 27-28's sectors
  };
  const nlohmann::json off = summary("off", " --blocked-hold 0");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "obstacles[7] (chair)");
  EXPECT_LT(off["first_collision_s"].get<double>(), 6.0);
  const nlohmann::json on = summary("on", " --blocked-hold 0.5");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  EXPECT_GE(on["turns"].get<long>(), 1);  // held back, it turns away instead
  std::filesystem::remove_all(dir);
}

TEST(ExploreCli, TakesTheSideBranchOfATMetFromItsBar) {
  const auto out = TempDir("tee");
  std::filesystem::create_directories(out.parent_path());
  const auto world = std::filesystem::temp_directory_path() / "squint_apps_explore_tee.yaml";
  {
    std::ofstream w(world);
    w << "format: squint-world/1\nname: t-junction\nambient: 0.12\n"
         "camera: {height_m: 0.60, pitch_deg: -3.0, hfov_deg: 60.0, width: 320, height: 240}\n"
         "robot: {radius_m: 0.25, max_speed_mps: 0.6, max_turn_rate_dps: 90, start: [2.0, 0.0, 0.0]}\n"
         "corridor_defaults: {width_m: 2.0, height_m: 2.8, floor: tiles, wall: paint, ceiling: ceiling,\n"
         "  lights: {rows: centre, spacing_m: 3.0, size_m: [1.2, 0.3]}}\n"
         "corridors:\n"
         "  - {name: bar, from: [0, 0], to: [24, 0]}\n"
         "  - {name: stem, from: [12, 0], to: [12, -10]}\n";
  }
  const CliResult r = RunSquint("explore --world " + world.string() + " --minutes 2 --seed 1 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.all();
  std::ifstream js(out / "summary.json");
  const nlohmann::json j = nlohmann::json::parse(js);
  EXPECT_EQ(j["collisions"].get<long>(), 0);
  EXPECT_GT(j["coverage"].get<double>(), 0.8);
  std::ifstream ev(out / "events.csv");
  std::string line;
  bool junction = false, turned_into_stem = false;
  while (std::getline(ev, line)) {
    if (line.find(",junction,") != std::string::npos) junction = true;
    // t_s,kind,true_x_m,true_y_m,true_yaw_deg,odom_x_m,odom_y_m,node,turn_deg,note
    if (line.find(",turn,") == std::string::npos) continue;
    std::stringstream ss(line);
    std::string cell[9];
    for (std::string& c : cell) std::getline(ss, c, ',');
    const double x = std::stod(cell[2]), y = std::stod(cell[3]);
    if (cell[8] == "-90" && std::abs(x - 12.0) < 1.0 && std::abs(y) < 0.8) turned_into_stem = true;
  }
  EXPECT_TRUE(junction);
  EXPECT_TRUE(turned_into_stem);
  std::filesystem::remove_all(out);
  std::filesystem::remove(world);
}

// `default`, seed 1, with --wall-line-align: the robot drives the south stem, comes back up it to
// the T at (20, 0), stops inside the stem's mouth, turns west (the bar it came along) and stalls
// right after setting off (182.7 s): that branch is closed, and with the east side judged a wall
// the T is a dead end for good. The 45-minute run then shuttles between the T and the stem's dead
// end (coverage 0.21). With --reopen-blocked-driven the west branch is open again on the next
// arrival (239 s): the robot sets off west from another stop and passes junction 0 at x = 11.3.
// The latest time (after 200 s) at which the robot stood west of x = 15: none without. (With
// --far-floor-from 0, as before session 36: with its default of 2 the robot takes another route.)
double LastTimeWestOf(const std::filesystem::path& out, double x_max, double after_s) {
  std::ifstream tr(out / "trace.csv");
  std::string line;
  std::getline(tr, line);  // t_s,true_x_m,...
  double last = -1.0;
  while (std::getline(tr, line)) {
    std::stringstream ss(line);
    std::string t, x;
    std::getline(ss, t, ',');
    std::getline(ss, x, ',');
    if (std::stod(t) > after_s && std::stod(x) < x_max) last = std::stod(t);
  }
  return last;
}

TEST(ExploreCli, ADrivenCorridorBlockedAtSetOffIsTriedAgainOnTheNextArrival) {
  const auto dir = TempDir("reopen-blocked-driven");
  const std::string run = "--world default --seed 1 --minutes 4.5 --wall-line-align --far-floor-from 0" + kBeforeSession45;
  const nlohmann::json closed = ExploreSummary(dir / "closed", run);
  EXPECT_EQ(closed["collisions"].get<long>(), 0);
  EXPECT_LT(LastTimeWestOf(dir / "closed", 15.0, 200.0), 0.0);
  const nlohmann::json reopened = ExploreSummary(dir / "reopened", run + " --reopen-blocked-driven");
  EXPECT_EQ(reopened["collisions"].get<long>(), 0);
  EXPECT_GT(LastTimeWestOf(dir / "reopened", 15.0, 200.0), 250.0);
  std::filesystem::remove_all(dir);
}

TEST(ExploreCli, UnknownWorldIsOneClearLine) {
  const auto out = TempDir("bad");
  const CliResult r = RunSquint("explore --world no-such-world --minutes 0.1 --out " + out.string());
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.all().find("squint: error:"), std::string::npos) << r.all();
  EXPECT_NE(r.all().find("no-such-world"), std::string::npos) << r.all();
  EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(ExploreCli, NonPositiveMinutesIsRejected) {
  const auto out = TempDir("minutes");
  for (const char* minutes : {"0", "-1", "nan", "abc"}) {
    const CliResult r = RunSquint(std::string("explore --minutes ") + minutes + " --out " + out.string());
    EXPECT_NE(r.code, 0) << minutes;
    // One readable line naming the option (CLI11's own range message spells out the largest double).
    EXPECT_NE(r.err.find("--minutes: must be a number > 0"), std::string::npos) << r.all();
    EXPECT_LT(r.err.find('\n'), 80u) << r.all();
    EXPECT_FALSE(std::filesystem::exists(out));
  }
}

}  // namespace

namespace {

// `squint eval compare-explore`: a set of real `eval explore` runs compared with itself (a round
// trip: every run matched, none changed, the same figures on both sides), the report also written
// with --out, and bad input as one error line with a non-zero exit.
TEST(ExploreCli, CompareExploreMatchesASetWithItselfAndNamesBadInput) {
  const auto dir = TempDir("compare");
  const CliResult run = RunSquint("eval explore --world corridor-0 --starts 2 --minutes 0.1 --seed 3 --out " +
                                  (dir / "set" / "seed-3").string());
  ASSERT_EQ(run.code, 0) << run.all();
  const CliResult r = RunSquint("eval compare-explore " + (dir / "set").string() + " " +
                                (dir / "set" / "seed-3" / "runs.csv").string() + " --out " + (dir / "report.md").string());
  // The folder of seed folders labels its runs seed-3, the single file does not: nothing shared.
  EXPECT_NE(r.code, 0);
  EXPECT_NE(r.err.find("share no run"), std::string::npos) << r.all();
  EXPECT_FALSE(std::filesystem::exists(dir / "report.md"));

  const CliResult same = RunSquint("eval compare-explore " + (dir / "set").string() + " " + (dir / "set").string() +
                                   " --out " + (dir / "report.md").string());
  ASSERT_EQ(same.code, 0) << same.all();
  EXPECT_NE(same.out.find("Runs compared: 2 (0 changed); left out, in one set only: 0 in BASE, 0 in NEW."),
            std::string::npos)
      << same.out;
  EXPECT_NE(same.out.find("Coverage, NEW - BASE, paired: +0.0000 +- 0.0000"), std::string::npos) << same.out;
  EXPECT_NE(same.out.find("0 only in NEW, 0 only in BASE"), std::string::npos) << same.out;
  std::ifstream in(dir / "report.md");
  std::stringstream written;
  written << in.rdbuf();
  EXPECT_EQ(written.str(), same.out);

  const CliResult missing = RunSquint("eval compare-explore " + (dir / "set").string() + " " + (dir / "none").string());
  EXPECT_NE(missing.code, 0);
  EXPECT_NE(missing.err.find((dir / "none").string() + ": no such file or folder"), std::string::npos) << missing.all();
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;
  std::filesystem::remove_all(dir);
}

// Two of session 39's defaults' seven failing seeded starts, set-offs far off the axis: corridor-8's
// start 2 of seed 61 (the glance's axis 36° from the walls' lines; the wall met at 2.3 s) and
// `default`'s start 4 of seed 74 (41°; met at 35.1 s). With --wall-line-align-over 25 (the default
// since session 45) the lines override the glance there, and neither meets anything in those 40 s.
// Both runs leave session 43's two switches off, as session 39's defaults did.
TEST(ExploreCli, WallLinesOverrideAGlanceFarOffTheAxisAtTheSetOff) {
  const auto dir = TempDir("wall-line-align-over");
  const std::string c8 = "--world corridor-8 --seed 61 --eval-start 2 --minutes 0.67";
  const std::string d74 = "--world default --seed 74 --eval-start 4 --minutes 0.67";
  for (const std::string& start : {c8, d74}) {
    SCOPED_TRACE(start);
    const nlohmann::json off = ExploreSummary(dir / "off", start + kBeforeSession45);
    EXPECT_GT(off["collisions"].get<long>(), 0);
    EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
    EXPECT_EQ(off["align_line_overrides"].get<long>(), 0);
    const nlohmann::json on = ExploreSummary(dir / "on", start + RulesOffBut(Session45Rules(), "--wall-line-align-over"));
    EXPECT_EQ(on["collisions"].get<long>(), 0);
    EXPECT_GE(on["align_line_overrides"].get<long>(), 1);
  }
  std::filesystem::remove_all(dir);
}

// Session 43's two switches (defaults since session 45) on the seeded starts they were made for,
// each turned off and on with everything else as when it was made. corridor-7's start 4 of seed
// 23 with --wall-line-align-over 25: the look around sets off toward a door 0.7 m away (its
// entropy 0.83 of the corridor's) and meets it at 16.3 s; with --scan-entropy-floor 0.9 it sets off
// along the corridor. corridor-1's start 9 of seed 94 (with session 39's defaults): the drive to
// the cross corridor's centre line is held by a wall filling the view, the robot turns 0.5 m off
// that line and meets the mouth's corner at 156.4 s; with --shift-trusts-points 1.2 it drives
// there and meets nothing.
TEST(ExploreCli, ScanEntropyFloorAndShiftTrustsPointsClearTheirStarts) {
  const auto dir = TempDir("session43-switches");
  struct Case {
    std::string start, off, on;
  };
  for (const Case& k : {Case{"--world corridor-7 --seed 23 --eval-start 4 --minutes 0.5 --shift-trusts-points 0", "--scan-entropy-floor 0",
                             "--scan-entropy-floor 0.9"},
                        Case{"--world corridor-1 --seed 94 --eval-start 9 --minutes 2.7" + RulesOffBut(Session45Rules(), "--shift-trusts-points"),
                             "--shift-trusts-points 0", "--shift-trusts-points 1.2"}}) {
    SCOPED_TRACE(k.start);
    const nlohmann::json off = ExploreSummary(dir / "off", k.start + " " + k.off);
    EXPECT_GT(off["collisions"].get<long>(), 0);
    EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
    EXPECT_EQ(off["scan_entropy_skips"].get<long>(), 0);
    const nlohmann::json on = ExploreSummary(dir / "on", k.start + " " + k.on);
    EXPECT_EQ(on["collisions"].get<long>(), 0);
    if (k.on.find("entropy") != std::string::npos) {
      EXPECT_GE(on["scan_entropy_skips"].get<long>(), 1);
    }
  }
  std::filesystem::remove_all(dir);
}

// corridor-2's start 2 of seed 97 (session 45's defaults): 0.35 m from the west wall, where the
// carpet and the panels have one grey (the visual sonar reads nothing), the glance's axis 7° off;
// the robot sets off 5° toward the wall and meets it at 37.7 s. With --wall-keep 0.45 the walls'
// lines, which measure that wall, bound its heading and it meets nothing.
TEST(ExploreCli, WallKeepClearsASetOffBesideAWallOfTheFloorsGrey) {
  const auto dir = TempDir("wall-keep");
  // As found: the defaults of sessions 45-48.
  const std::string start = "--world corridor-2 --seed 97 --eval-start 2 --minutes 0.7" + RulesOffBut(Session49Rules(), "--wall-keep");
  const nlohmann::json off = ExploreSummary(dir / "off", start + " --wall-keep 0");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
  EXPECT_EQ(off["wall_keep_frames"].get<long>(), 0);
  const nlohmann::json on = ExploreSummary(dir / "on", start + " --wall-keep 0.45");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  EXPECT_GT(on["wall_keep_frames"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// corridor-9's start 4 of seed 40 (the defaults) and start 5 of seed 67 (with --wall-keep 0.45),
// both near the T's bar, 0.4 m from a side wall of brick: a look around whose axis is 20° off
// takes the one direction whose free travel the wall's mortar courses, read as floor boundaries,
// make 1.1-1.2 m (the others 0.25-0.3 m), though its glance entropy is a wall's (0.63 of the best),
// and the robot sets off into that wall (32.4 s; 40.5 s). With --scan-wall-entropy 0.7 the scan
// does not take it and neither run meets anything in that time.
TEST(ExploreCli, ScanWallEntropyKeepsALookAroundOffABrickWallUpClose) {
  const auto dir = TempDir("scan-wall-entropy");
  // As found: the defaults of sessions 45-48 (with --wall-keep 0.45 alone for the second).
  for (const std::string& start :
       {"--world corridor-9 --seed 40 --eval-start 4 --minutes 0.6" + RulesOffBut(Session49Rules(), "--scan-wall-entropy"),
        std::string("--world corridor-9 --seed 67 --eval-start 5 --minutes 0.75 --wall-keep 0.45 --wall-keep-min 0 --no-own-range-driving")}) {
    SCOPED_TRACE(start);
    const nlohmann::json off = ExploreSummary(dir / "off", start + " --scan-wall-entropy 0");
    EXPECT_GT(off["collisions"].get<long>(), 0);
    EXPECT_EQ(off["first_hit"].get<std::string>(), "wall");
    EXPECT_EQ(off["scan_wall_entropy_skips"].get<long>(), 0);
    const nlohmann::json on = ExploreSummary(dir / "on", start + " --scan-wall-entropy 0.7");
    EXPECT_EQ(on["collisions"].get<long>(), 0);
    EXPECT_GE(on["scan_wall_entropy_skips"].get<long>(), 1);
  }
  std::filesystem::remove_all(dir);
}

// The obstacle course's start 7 of seed 67 with --wall-keep 0.45: setting off at 153.5 s beside the
// chair at (8.5, -1.2), the walls' lines' parallel line lay 0.18 m to the right of the robot's
// centre (a flat line on the floor: no wall stands inside the disc while it touches nothing), the
// rule turned the robot 21° left and it met the chair at 155.1 s. With --wall-keep-min 0.25 such
// a line is left out and the run meets nothing; corridor-2 97/2's wall, 0.35 m away, is still kept
// off.
TEST(ExploreCli, WallKeepLeavesOutALineInsideTheDisc) {
  const auto dir = TempDir("wall-keep-min");
  const std::string oc = "--world obstacle-course --seed 67 --eval-start 7 --minutes 2.6 --wall-keep 0.45 --scan-wall-entropy 0 --no-own-range-driving";
  const nlohmann::json off = ExploreSummary(dir / "off", oc + " --wall-keep-min 0");
  EXPECT_GT(off["collisions"].get<long>(), 0);
  EXPECT_EQ(off["first_hit"].get<std::string>(), "obstacles[3] (chair)");
  EXPECT_GT(off["wall_keep_frames"].get<long>(), 0);
  const nlohmann::json on = ExploreSummary(dir / "on", oc + " --wall-keep-min 0.25");
  EXPECT_EQ(on["collisions"].get<long>(), 0);
  const nlohmann::json c2 = ExploreSummary(dir / "c2", "--world corridor-2 --seed 97 --eval-start 2 --minutes 0.7 --wall-keep 0.45 --wall-keep-min 0.25 --scan-wall-entropy 0 --no-own-range-driving");
  EXPECT_EQ(c2["collisions"].get<long>(), 0);
  EXPECT_GT(c2["wall_keep_frames"].get<long>(), 0);
  std::filesystem::remove_all(dir);
}

// --own-range-driving (off by default): the defaults' two failing seeded starts in the obstacle
// course. 30/6: set off at 126 s beside the chair at (8.5, -1.2), whose nearest leg, 4 cm thick,
// the sonar's median across columns had voted out of the memory, and met it with the flank at
// 127.9 s. 64/5: set off past the rotated box's corner, which the memory held 0.2 m too far, and
// met it at 137.1 s. With what the columns' own readings do not clear kept for driving only,
// neither meets anything in the same time.
TEST(ExploreCli, OwnRangeDrivingKeepsAChairLegAndABoxCornerOffTheFlank) {
  const auto dir = TempDir("own-range-driving");
  const std::pair<std::string, std::string> starts[] = {{"--seed 30 --eval-start 6", "obstacles[3] (chair)"},
                                                        {"--seed 64 --eval-start 5", "obstacles[5] (box)"}};
  for (const auto& [start, hit] : starts) {
    SCOPED_TRACE(start);
    // As found: the defaults of sessions 45-48.
    const std::string run = "--world obstacle-course --minutes 2.4 " + start + RulesOffBut(Session49Rules(), "--own-range-driving");
    const nlohmann::json off = ExploreSummary(dir / "off", run + " --no-own-range-driving");
    EXPECT_GT(off["collisions"].get<long>(), 0);
    EXPECT_EQ(off["first_hit"].get<std::string>(), hit);
    EXPECT_GT(off["first_collision_s"].get<double>(), 120.0);
    const nlohmann::json on = ExploreSummary(dir / "on", run + " --own-range-driving");
    EXPECT_EQ(on["collisions"].get<long>(), 0);
    EXPECT_EQ(on["first_hit"].get<std::string>(), "");
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
