// Visual sonar and obstacle memory on constructed inputs: images whose floor-boundary rows are
// known give the camera model's floor ranges; uniform views read as blocked near; isolated
// texture steps are voted out; remembered boundaries limit the free travel as the robot moves.
#include "squint/explore/visual_sonar.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/explore/explorer.hpp"
#include "squint/explore/obstacle_memory.hpp"
#include "default_camera.hpp"

namespace squint::explore {
namespace {

// The default world's camera at 64×48.
CameraModel SonarCamera() { return testing::DefaultWorldCamera(64, 48); }

struct Image {
  std::vector<std::uint8_t> px;
  int w = 64, h = 48;
  Image() : px(64 * 48, 0) {}
  std::uint8_t& At(int u, int v) { return px[static_cast<std::size_t>(v * w + u)]; }
  GrayView View() const { return {px.data(), w, h, w}; }
};

// Floor (bright, slightly textured) below `boundary[u]` (the lowest wall row), wall above.
Image FloorWall(const std::vector<int>& boundary) {
  Image im;
  for (int u = 0; u < im.w; ++u)
    for (int v = 0; v < im.h; ++v) im.At(u, v) = v > boundary[static_cast<std::size_t>(u)] ? 180 + ((u + v) % 3) : 120;
  return im;
}

TEST(VisualSonar, KnownBoundaryRowsGiveTheFloorRangeOfThatRow) {
  const CameraModel cam = SonarCamera();
  VisualSonar sonar(cam);
  std::vector<int> rows(64);
  for (int u = 0; u < 64; ++u) rows[static_cast<std::size_t>(u)] = 30 + (u / 16) * 3;  // 30, 33, 36, 39 by blocks of 16
  const Image im = FloorWall(rows);
  const auto& out = sonar.Process(im.View());
  ASSERT_EQ(out.size(), 64u);
  for (int u = 0; u < 64; ++u) {
    if (u % 16 < 4 || u % 16 > 11) continue;  // away from the block edges (the median spans 7 columns)
    const SonarColumn& c = out[static_cast<std::size_t>(u)];
    ASSERT_EQ(c.kind, SonarReturn::kBoundary) << "column " << u;
    // Independent answer: the floor point of the boundary between the wall row and the floor row,
    // in this column or one of the median's neighbours (same row, nearly the same range).
    const int row = rows[static_cast<std::size_t>(u)];
    double lo = 1e9, hi = 0.0;
    for (int x = u - 3; x <= u + 3; ++x) {
      const auto fp = cam.FloorPoint({static_cast<double>(x), row + 0.5});
      ASSERT_TRUE(fp.has_value());
      lo = std::min(lo, fp->norm());
      hi = std::max(hi, fp->norm());
    }
    EXPECT_GE(c.range_m, lo - 1e-9) << "column " << u;
    EXPECT_LE(c.range_m, hi + 1e-9) << "column " << u;
    EXPECT_NEAR(c.bearing_rad, cam.BearingOfColumn(u), 1e-12);
    if (c.boundary_row >= 0) {
      EXPECT_EQ(c.boundary_row, row);
    }
  }
  // Lower rows are nearer: the range grows from block to block upward.
  EXPECT_GT(out[8].range_m, out[24].range_m);
  EXPECT_GT(out[24].range_m, out[40].range_m);
  EXPECT_GT(out[40].range_m, out[56].range_m);
}

TEST(VisualSonar, WallAtKnownDistanceReadsThatDistanceAhead) {
  const CameraModel cam = SonarCamera();
  VisualSonar sonar(cam);
  // A wall across the view 2.0 m ahead: its base projects to one row per column.
  std::vector<int> rows(64);
  for (int u = 0; u < 64; ++u) {
    const double bearing = cam.BearingOfColumn(u);
    const auto px = cam.Project({2.0, 2.0 * std::tan(bearing), 0.0});
    ASSERT_TRUE(px.has_value());
    rows[static_cast<std::size_t>(u)] = static_cast<int>(std::floor(px->y()));  // the lowest wall row
  }
  const auto& out = sonar.Process(FloorWall(rows).View());
  for (int u = 4; u < 60; ++u) {
    const SonarColumn& c = out[static_cast<std::size_t>(u)];
    ASSERT_EQ(c.kind, SonarReturn::kBoundary);
    // Along x (forward) the wall is at 2.0 m; one row of quantisation at 2 m is about 0.1 m.
    EXPECT_NEAR(c.range_m * std::cos(c.bearing_rad), 2.0, 0.12) << "column " << u;
  }
}

// A view straight ahead made of horizontal bands: for each column, the lowest row of each band
// is where a robot-frame point (x ahead at that column's bearing, height z) projects. Bands are
// given bottom-up as (x_m, z_m, grey); below the first band the floor is bright tiles.
Image Bands(const CameraModel& cam, const std::vector<std::array<double, 3>>& bands) {
  Image im;
  for (int u = 0; u < im.w; ++u) {
    const double t = std::tan(cam.BearingOfColumn(u));
    std::vector<int> starts;
    for (const auto& b : bands) {
      const auto px = cam.Project({b[0], b[0] * t, b[1]});
      starts.push_back(px ? static_cast<int>(std::floor(px->y())) : -1);
    }
    for (int v = 0; v < im.h; ++v) {
      int grey = 180 + ((u + v) % 3);  // tiles
      for (std::size_t i = 0; i < bands.size(); ++i)
        if (v <= starts[i]) grey = static_cast<int>(bands[i][2]);
      im.At(u, v) = static_cast<std::uint8_t>(grey);
    }
  }
  return im;
}

TEST(VisualSonar, CarpetEdgeAtKnownRangeIsFloorAndTheWallBeyondIsTheBoundary) {
  const CameraModel cam = SonarCamera();
  VisualSonar sonar(cam);
  // Tiles to 2.0 m, dark carpet (on the floor, z = 0) from 2.0 m to a wall base at 3.5 m.
  const Image im = Bands(cam, {{2.0, 0.0, 110.0}, {3.5, 0.0, 160.0}});
  const auto& out = sonar.Process(im.View());
  for (int u = 4; u < 60; ++u) {
    const SonarColumn& c = out[static_cast<std::size_t>(u)];
    ASSERT_EQ(c.kind, SonarReturn::kBoundary) << "column " << u;
    // One row at 3.5 m is about 0.35 m of range; the carpet edge is not what the column reads.
    EXPECT_NEAR(c.range_m * std::cos(c.bearing_rad), 3.5, 0.3) << "column " << u;
    if (c.boundary_row >= 0) {
      EXPECT_NEAR(c.floor_edge_m * std::cos(c.bearing_rad), 2.0, 0.12) << "column " << u;
    }
  }
  // Turned off, the carpet edge is read as something standing at 2.0 m.
  VisualSonarOptions off;
  off.floor_edge_max_ratio = 0.0;
  VisualSonar plain(cam, off);
  const auto& out2 = plain.Process(im.View());
  for (int u = 4; u < 60; ++u) EXPECT_NEAR(out2[static_cast<std::size_t>(u)].range_m * std::cos(out2[static_cast<std::size_t>(u)].bearing_rad), 2.0, 0.12);
}

TEST(VisualSonar, WallBaseLowObstacleAndNearFloorEdgeStayStanding) {
  const CameraModel cam = SonarCamera();
  VisualSonar sonar(cam);
  // (a) A wall at 2.0 m rising through the horizon, with a grey band from 0.02 to 0.10 m (a
  // skirting board: its top edge lies at 1.2 × the base range as floor) and a dark dado band from
  // 0.45 m up (above the camera: 0.6 m, at 4 × the base range as floor).
  // (b) A box 0.40 m high at 1.9 m with floor beyond (its top edge lies at 3 × its range as
  // floor: above floor_edge_max_ratio). (c) A carpet edge nearer than floor_edge_min_range_m
  // (1.5 m, carpet to a wall at 2.6 m) is, conservatively, read as standing.
  struct Case {
    const char* name;
    std::vector<std::array<double, 3>> bands;
    double range_m;
  };
  const std::vector<Case> cases = {
      {"skirted wall", {{2.0, 0.0, 90.0}, {2.0, 0.10, 130.0}, {2.0, 0.45, 60.0}}, 2.0},
      {"plain wall", {{2.0, 0.0, 120.0}}, 2.0},
      {"low box", {{1.9, 0.0, 90.0}, {1.9, 0.40, 180.0}}, 1.9},
      {"near carpet edge", {{1.5, 0.0, 110.0}, {2.6, 0.0, 160.0}}, 1.5},
  };
  for (const Case& k : cases) {
    const auto& out = sonar.Process(Bands(cam, k.bands).View());
    for (int u = 4; u < 60; ++u) {
      const SonarColumn& c = out[static_cast<std::size_t>(u)];
      ASSERT_EQ(c.kind, SonarReturn::kBoundary) << k.name << ", column " << u;
      EXPECT_NEAR(c.range_m * std::cos(c.bearing_rad), k.range_m, 0.12) << k.name << ", column " << u;
      EXPECT_EQ(c.floor_edge_m, 0.0) << k.name << ", column " << u;
    }
  }
}

TEST(VisualSonar, FloorEdgeOptionsAreValidated) {
  VisualSonarOptions o;
  o.floor_edge_min_ratio = 1.0;
  EXPECT_FALSE(o.Validate().empty());
  o.floor_edge_min_ratio = 3.0;  // above the maximum
  EXPECT_FALSE(o.Validate().empty());
  o.floor_edge_max_ratio = 0.0;  // off: the minimum does not matter
  EXPECT_TRUE(o.Validate().empty());
  o.floor_edge_min_rows = 0;
  EXPECT_FALSE(o.Validate().empty());
}

TEST(VisualSonar, UniformViewIsBlockedNearAndFloorToTheHorizonIsFar) {
  const CameraModel cam = SonarCamera();
  VisualSonar sonar(cam);
  Image wall;
  for (auto& p : wall.px) p = 130;
  for (const SonarColumn& c : sonar.Process(wall.View())) {
    EXPECT_EQ(c.kind, SonarReturn::kBlockedNear);
    EXPECT_EQ(c.range_m, 0.0);
  }
  // Floor up to the row above the horizon: a step there is beyond any range.
  const int horizon = static_cast<int>(std::floor(cam.HorizonRow()));
  const auto& far = sonar.Process(FloorWall(std::vector<int>(64, horizon - 1)).View());
  for (const SonarColumn& c : far) {
    EXPECT_EQ(c.kind, SonarReturn::kFar);
    EXPECT_EQ(c.range_m, sonar.Options().max_range_m);
  }
  EXPECT_GT(sonar.NearBlindRangeM(), 1.0);  // 0.6 m high, 26° below the axis at the bottom row
  EXPECT_LT(sonar.NearBlindRangeM(), 1.4);
}

TEST(VisualSonar, IsolatedTextureStepIsVotedOutByTheNeighbours) {
  const CameraModel cam = SonarCamera();
  VisualSonar sonar(cam);
  Image im = FloorWall(std::vector<int>(64, 30));
  // One dark floor tile in column 20 only, a few rows above the bottom.
  for (int v = 38; v <= 41; ++v) im.At(20, v) = 90;
  VisualSonarOptions no_median;
  no_median.median_half_width = 0;
  no_median.column_half_width = 0;
  VisualSonar raw(cam, no_median);
  EXPECT_LT(raw.Process(im.View())[20].range_m, sonar.RangeAt(20, 30) - 0.5);  // the raw column is fooled
  const auto& out = sonar.Process(im.View());
  EXPECT_EQ(out[20].kind, SonarReturn::kBoundary);
  EXPECT_GE(out[20].range_m, std::min(sonar.RangeAt(17, 30), sonar.RangeAt(23, 30)) - 1e-9);
  EXPECT_LE(out[20].range_m, std::max(sonar.RangeAt(17, 30), sonar.RangeAt(23, 30)) + 1e-9);
}

// A wall corner in the right half of the view, floor to the horizon in the left half: the median
// across columns is taken one rank nearer than the middle (median_near_bias), so the blocked side
// of the transition reaches one column farther toward the free side (with the plain median a
// column there read the far floor beside the corner, and the memory cleared the corner along that
// ray). Near boundaries keep the plain median: floor texture 3 raw columns wide (no column
// averaging here) is still voted out, as with the plain median.
TEST(VisualSonar, NearBiasedMedianKeepsTheNearSideOfATransition) {
  const CameraModel cam = SonarCamera();
  const int horizon = static_cast<int>(std::floor(cam.HorizonRow()));
  Image im = FloorWall(std::vector<int>(64, horizon - 1));
  for (int u = 32; u < 64; ++u)
    for (int v = 0; v < 48; ++v) im.At(u, v) = 120;  // the wall fills these columns down to the bottom
  VisualSonarOptions plain;
  plain.median_near_bias = 0;
  VisualSonarOptions biased;
  biased.median_near_bias = 1;
  VisualSonar a(cam, plain), b(cam, biased);
  auto first_blocked = [](const std::vector<SonarColumn>& cols) {
    for (std::size_t u = 0; u < cols.size(); ++u)
      if (cols[u].kind == SonarReturn::kBlockedNear) return static_cast<int>(u);
    return -1;
  };
  const std::vector<SonarColumn> pa = a.Process(im.View());
  const std::vector<SonarColumn> pb = b.Process(im.View());
  EXPECT_EQ(first_blocked(pb), first_blocked(pa) - 1);
  for (int u = 0; u < first_blocked(pb); ++u) EXPECT_EQ(pb[static_cast<std::size_t>(u)].kind, SonarReturn::kFar) << "column " << u;
  for (int u = first_blocked(pb); u < 64; ++u) EXPECT_EQ(pb[static_cast<std::size_t>(u)].kind, SonarReturn::kBlockedNear) << "column " << u;
  // Dark floor spots near the bottom, 2 and 3 columns wide (no column averaging).
  biased.column_half_width = 0;
  VisualSonar c(cam, biased);
  Image tex = FloorWall(std::vector<int>(64, 30));
  for (int v = 38; v <= 41; ++v) tex.At(15, v) = tex.At(16, v) = 90;
  for (int v = 38; v <= 41; ++v) tex.At(40, v) = tex.At(41, v) = tex.At(42, v) = 90;
  const auto& out = c.Process(tex.View());
  EXPECT_GE(out[15].range_m, std::min(c.RangeAt(12, 30), c.RangeAt(19, 30)) - 1e-9);  // voted out
  EXPECT_GE(out[41].range_m, std::min(c.RangeAt(38, 30), c.RangeAt(45, 30)) - 1e-9);  // voted out
}

// A post 3 columns wide standing on the floor near the robot (a chair leg), far floor beside it:
// the plain median over 7 columns votes it out; a boundary nearer than median_near_range_m wins
// one rank early, so the post's column reads the post's range. Beyond that range it is voted out
// either way (texture steps), and the option is validated.
TEST(VisualSonar, ThinPostCloseByWinsOneRankEarly) {
  CameraModel cam = SonarCamera();
  cam.pitch_deg = -10.0;  // floor from about 0.86 m in view
  Image im = FloorWall(std::vector<int>(64, 30));
  auto post = [&](int row) {
    for (int u = 40; u <= 42; ++u)
      for (int v = 0; v <= row; ++v) im.At(u, v) = 120;
  };
  post(42);
  VisualSonarOptions on;
  on.column_half_width = 0;
  VisualSonarOptions off = on;
  off.median_near_range_m = 0.0;
  VisualSonar a(cam, on), b(cam, off);
  // Readings are some column's range of that row within the median's 7 columns (38-44).
  auto span = [&](int row, double r) {
    double lo = 1e9, hi = 0.0;
    for (int u = 38; u <= 44; ++u) lo = std::min(lo, a.RangeAt(u, row)), hi = std::max(hi, a.RangeAt(u, row));
    return r >= lo - 1e-9 && r <= hi + 1e-9;
  };
  ASSERT_LT(a.RangeAt(41, 42), on.median_near_range_m - 0.05);
  EXPECT_TRUE(span(42, a.Process(im.View())[41].range_m)) << a.Process(im.View())[41].range_m;
  EXPECT_TRUE(span(30, b.Process(im.View())[41].range_m)) << b.Process(im.View())[41].range_m;
  // The same post 1.5 m away: voted out with the option too.
  im = FloorWall(std::vector<int>(64, 30));
  int far_row = 47;
  while (far_row > 30 && a.RangeAt(41, far_row) < 1.5) --far_row;
  post(far_row);
  EXPECT_TRUE(span(30, a.Process(im.View())[41].range_m)) << a.Process(im.View())[41].range_m;
  VisualSonarOptions bad;
  bad.median_near_range_m = -1.0;
  EXPECT_NE(bad.Validate(), "");
}

// The same post 1.5 m away is voted out of the median's range, but each column keeps its own
// reading (own_range_m): the post's columns their step's range, the floor's columns the wall's.
TEST(VisualSonar, OwnRangeKeepsAThinPostTheMedianVotesOut) {
  CameraModel cam = SonarCamera();
  cam.pitch_deg = -10.0;
  VisualSonarOptions opt;
  opt.column_half_width = 0;
  VisualSonar sonar(cam, opt);
  int row = 47;
  while (row > 30 && sonar.RangeAt(41, row) < 1.5) --row;
  Image im = FloorWall(std::vector<int>(64, 30));
  for (int u = 40; u <= 41; ++u)
    for (int v = 0; v <= row; ++v) im.At(u, v) = 120;
  const auto& out = sonar.Process(im.View());
  for (int u = 40; u <= 41; ++u) {
    EXPECT_NEAR(out[static_cast<std::size_t>(u)].own_range_m, sonar.RangeAt(u, row), 1e-9) << "column " << u;
    // Voted out: the median reads the wall's base (row 30) of some column within its 7.
    double lo = 1e9, hi = 0.0;
    for (int x = u - 3; x <= u + 3; ++x) lo = std::min(lo, sonar.RangeAt(x, 30)), hi = std::max(hi, sonar.RangeAt(x, 30));
    EXPECT_GE(out[static_cast<std::size_t>(u)].range_m, lo - 1e-9) << "column " << u;
    EXPECT_LE(out[static_cast<std::size_t>(u)].range_m, hi + 1e-9) << "column " << u;
    EXPECT_GT(out[static_cast<std::size_t>(u)].range_m, out[static_cast<std::size_t>(u)].own_range_m + 0.3) << "column " << u;
  }
  for (int u : {10, 30, 50}) EXPECT_NEAR(out[static_cast<std::size_t>(u)].own_range_m, out[static_cast<std::size_t>(u)].range_m, 1e-9);
}

// A wall filling the view with a bright line at the horizon in a few columns (a mortar course):
// those columns read far, but 5 of them are too few for a floor reference, so the rest stays
// blocked near (not "unknown", which would let the robot drive into the wall).
TEST(VisualSonar, StepsAtTheHorizonAreNoFloorReference) {
  const CameraModel cam = SonarCamera();
  VisualSonar sonar(cam);
  Image wall;
  for (auto& p : wall.px) p = 110;
  const int horizon = static_cast<int>(std::floor(cam.HorizonRow()));
  for (int u = 30; u <= 34; ++u)
    for (int v = 0; v < horizon; ++v) wall.At(u, v) = 160;
  const auto& out = sonar.Process(wall.View());
  for (int u = 0; u < 64; ++u) {
    if (u >= 20 && u <= 43) continue;
    EXPECT_EQ(out[static_cast<std::size_t>(u)].kind, SonarReturn::kBlockedNear) << "column " << u;
  }
  // With a reference from enough columns with a clear floor step in range, a uniform column
  // whose bottom looks like that floor is unknown.
  Image mixed = FloorWall(std::vector<int>(64, 30));
  for (int u = 0; u < 16; ++u)
    for (int v = 0; v < 48; ++v) mixed.At(u, v) = 181;  // floor-grey all the way up
  const auto& out2 = sonar.Process(mixed.View());
  for (int u = 0; u < 10; ++u) EXPECT_EQ(out2[static_cast<std::size_t>(u)].kind, SonarReturn::kUnknown) << "column " << u;
  for (int u = 24; u < 60; ++u) EXPECT_EQ(out2[static_cast<std::size_t>(u)].kind, SonarReturn::kBoundary) << "column " << u;
}

// Something dark standing within the blind range, taller than the camera: it fills its columns
// from the bottom row up to its top edge just above the horizon, so the only step those columns
// find is that edge, at the horizon: floor "all the way" (far). far_floor_max_diff makes a far
// column whose bottom rows are unlike the frame's floor (here 65 against about 181) blocked near.
// The floor to the horizon beside it stays far; a far column over floor-grey bottom rows (a floor
// of that grey to the horizon) stays far; the rule off reads the dark thing far, as before.
TEST(VisualSonar, AFarStepOverABottomUnlikeTheFloorIsSomethingStandingNear) {
  const CameraModel cam = SonarCamera();
  const int horizon = static_cast<int>(std::floor(cam.HorizonRow()));
  std::vector<int> rows(64, 30);                                   // a wall's base in range on the left...
  for (int u = 32; u < 64; ++u) rows[static_cast<std::size_t>(u)] = horizon - 1;  // ...floor to the horizon on the right
  Image im = FloorWall(rows);
  for (int u = 40; u < 52; ++u)
    for (int v = horizon; v < 48; ++v) im.At(u, v) = 65;  // the dark thing, its top edge where the far floor ends
  VisualSonarOptions o;
  EXPECT_EQ(o.far_floor_max_diff, 40.0);  // the default
  o.far_floor_max_diff = 0.0;
  VisualSonar off(cam, o);
  const auto& before = off.Process(im.View());
  for (int u = 42; u < 50; ++u) EXPECT_EQ(before[static_cast<std::size_t>(u)].kind, SonarReturn::kFar) << "column " << u;
  o.far_floor_max_diff = 40.0;
  VisualSonar on(cam, o);
  const auto& after = on.Process(im.View());
  for (int u = 42; u < 50; ++u) {
    EXPECT_EQ(after[static_cast<std::size_t>(u)].kind, SonarReturn::kBlockedNear) << "column " << u;
    EXPECT_EQ(after[static_cast<std::size_t>(u)].range_m, 0.0) << "column " << u;
  }
  for (int u = 56; u < 64; ++u) EXPECT_EQ(after[static_cast<std::size_t>(u)].kind, SonarReturn::kFar) << "column " << u;
  for (int u = 4; u < 28; ++u) EXPECT_EQ(after[static_cast<std::size_t>(u)].kind, SonarReturn::kBoundary) << "column " << u;
  // The same thing in the floor's grey (within the limit): far, as the floor it resembles.
  Image grey = im;
  for (int u = 40; u < 52; ++u)
    for (int v = horizon; v < 48; ++v) grey.At(u, v) = 181 - 30;
  const auto& same = on.Process(grey.View());
  for (int u = 42; u < 50; ++u) EXPECT_EQ(same[static_cast<std::size_t>(u)].kind, SonarReturn::kFar) << "column " << u;
  o.far_floor_max_diff = -1.0;
  EXPECT_NE(o.Validate().find("far_floor_max_diff"), std::string::npos);
}

// Something standing within the blind range a little lower than the camera: its dark face fills
// columns 40-51 from the bottom row up to its top edge, which lies below the horizon where the
// floor beside it ends at a wall's base about 4 m away (the default building's bin, start 7 of
// seed 70). Those columns' only step is that top edge, a boundary in range, so far_floor_max_diff
// alone (far steps) reads them as floor running 3.8 m. With far_floor_from_m under that range
// they are blocked near; beyond it, or with far_floor_max_diff off, they read the boundary
// as before. The floor beside, with its step at the same row, stays a boundary.
TEST(VisualSonar, AStepInRangeOverABottomUnlikeTheFloorIsSomethingStandingNearFromAChosenRange) {
  const CameraModel cam = SonarCamera();
  const int horizon = static_cast<int>(std::floor(cam.HorizonRow()));
  const int edge = horizon + 9;  // the wall's base beside the thing, and the thing's top edge: 3.8 m
  std::vector<int> rows(64, 38);  // a nearer wall's base on the left
  for (int u = 32; u < 64; ++u) rows[static_cast<std::size_t>(u)] = edge;
  Image im = FloorWall(rows);
  for (int u = 40; u < 52; ++u)
    for (int v = edge + 1; v < 48; ++v) im.At(u, v) = 65;
  VisualSonarOptions o;
  EXPECT_EQ(o.far_floor_from_m, 2.0);  // the default since session 36
  o.far_floor_from_m = 0.0;            // far steps only
  VisualSonar plain(cam, o);
  const auto& before = plain.Process(im.View());
  const double range = before[45].range_m;  // the top edge read as the floor's end
  ASSERT_EQ(before[45].kind, SonarReturn::kBoundary);
  ASSERT_GT(range, 2.0);
  ASSERT_LT(range, 6.0);
  for (int u = 42; u < 50; ++u) EXPECT_EQ(before[static_cast<std::size_t>(u)].kind, SonarReturn::kBoundary) << "column " << u;

  o.far_floor_from_m = range - 0.5;
  VisualSonar on(cam, o);
  const auto& after = on.Process(im.View());
  for (int u = 42; u < 50; ++u) {
    EXPECT_EQ(after[static_cast<std::size_t>(u)].kind, SonarReturn::kBlockedNear) << "column " << u;
    EXPECT_EQ(after[static_cast<std::size_t>(u)].range_m, 0.0) << "column " << u;
  }
  for (int u = 56; u < 64; ++u) {
    EXPECT_EQ(after[static_cast<std::size_t>(u)].kind, SonarReturn::kBoundary) << "column " << u;
    EXPECT_EQ(after[static_cast<std::size_t>(u)].range_m, before[static_cast<std::size_t>(u)].range_m) << "column " << u;
  }
  for (int u = 4; u < 28; ++u) EXPECT_EQ(after[static_cast<std::size_t>(u)].kind, SonarReturn::kBoundary) << "column " << u;

  o.far_floor_from_m = range + 1.0;  // the step lies nearer than where the test starts
  VisualSonar beyond(cam, o);
  const auto& nearer = beyond.Process(im.View());
  for (int u = 42; u < 50; ++u) EXPECT_EQ(nearer[static_cast<std::size_t>(u)].kind, SonarReturn::kBoundary) << "column " << u;
  o.far_floor_from_m = range - 0.5;
  o.far_floor_max_diff = 0.0;  // the test itself off
  VisualSonar off(cam, o);
  const auto& none = off.Process(im.View());
  for (int u = 42; u < 50; ++u) EXPECT_EQ(none[static_cast<std::size_t>(u)].kind, SonarReturn::kBoundary) << "column " << u;
  o.far_floor_from_m = -1.0;
  EXPECT_NE(o.Validate().find("far_floor_from_m"), std::string::npos);
}

// The same dark thing filling most of the view (columns 16-63) up to the horizon: the columns
// reading far outnumber those with a wall's base in range (0-15), the frame's floor reference (the
// median bottom of the columns with a step) becomes the thing's own grey and far_floor_max_diff
// finds nothing unlike it. With floor_ref_boundaries the reference comes from the columns with a
// base in range: the thing's columns are blocked near. Without enough such columns (all 64 far) the
// far columns make the reference as before.
TEST(VisualSonar, AFloorReferenceFromBaseColumnsSeesAThingFillingMostOfTheView) {
  const CameraModel cam = SonarCamera();
  const int horizon = static_cast<int>(std::floor(cam.HorizonRow()));
  std::vector<int> rows(64, 30);
  for (int u = 16; u < 64; ++u) rows[static_cast<std::size_t>(u)] = horizon - 1;
  Image im = FloorWall(rows);
  for (int u = 16; u < 64; ++u)
    for (int v = horizon; v < 48; ++v) im.At(u, v) = 65;
  VisualSonarOptions o;
  EXPECT_FALSE(o.floor_ref_boundaries);  // the default
  VisualSonar off(cam, o);
  const auto& before = off.Process(im.View());
  for (int u = 20; u < 60; ++u) EXPECT_EQ(before[static_cast<std::size_t>(u)].kind, SonarReturn::kFar) << "column " << u;
  o.floor_ref_boundaries = true;
  VisualSonar on(cam, o);
  const auto& after = on.Process(im.View());
  for (int u = 20; u < 60; ++u) EXPECT_EQ(after[static_cast<std::size_t>(u)].kind, SonarReturn::kBlockedNear) << "column " << u;
  for (int u = 4; u < 12; ++u) EXPECT_EQ(after[static_cast<std::size_t>(u)].kind, SonarReturn::kBoundary) << "column " << u;
  // Floor to the horizon everywhere (no base in range): the far columns are the reference, far.
  const Image open = FloorWall(std::vector<int>(64, horizon - 1));
  const auto& far = on.Process(open.View());
  for (int u = 4; u < 60; ++u) EXPECT_EQ(far[static_cast<std::size_t>(u)].kind, SonarReturn::kFar) << "column " << u;
}

// A floor without contrast to the walls, seen down a corridor: no step anywhere, but the grey
// changes smoothly by 60 levels from the bottom row to the horizon (perspective shading). That is
// floor, not a wall filling the view: unknown. A view of one surface (within 10 levels from the
// bottom to the horizon) stays blocked near; with the rule off the gradient is blocked near too.
TEST(VisualSonar, SmoothFloorGradientWithoutReferenceIsUnknownNotBlocked) {
  const CameraModel cam = SonarCamera();
  const int horizon = static_cast<int>(std::floor(cam.HorizonRow()));
  auto ramp = [&](int levels) {
    Image im;
    for (int v = 0; v < im.h; ++v) {
      const double f = std::clamp((im.h - 1.0 - v) / (im.h - 1.0 - horizon), 0.0, 1.0);  // 0 bottom, 1 at the horizon
      for (int u = 0; u < im.w; ++u) im.At(u, v) = static_cast<std::uint8_t>(100 + levels * f + ((u + v) % 2));
    }
    return im;
  };
  VisualSonar sonar(cam);
  const Image floor = ramp(60);
  // The ramp's steepest rows differ by ~3 levels: no step.
  for (const SonarColumn& c : sonar.Process(floor.View())) EXPECT_EQ(c.kind, SonarReturn::kUnknown);
  const Image wall = ramp(10);
  for (const SonarColumn& c : sonar.Process(wall.View())) EXPECT_EQ(c.kind, SonarReturn::kBlockedNear);
  VisualSonarOptions off;
  off.gradient_unknown_levels = 0.0;
  VisualSonar old(cam, off);
  for (const SonarColumn& c : old.Process(floor.View())) EXPECT_EQ(c.kind, SonarReturn::kBlockedNear);
}

// Grey level with a small deterministic noise (render noise of the simulator's frames: +-3).
std::uint8_t Noisy(double level, int u, int v) {
  const unsigned hsh = (static_cast<unsigned>(u) * 73856093u) ^ (static_cast<unsigned>(v) * 19349663u);
  return static_cast<std::uint8_t>(std::clamp(level + static_cast<double>(hsh % 7u) - 3.0, 0.0, 255.0));
}

// Brick courses (a bright mortar row every `period` rows over a grey of 100) in columns [0, brick_to),
// a plain wall (grey 130) beyond; both with noise. All eight 8-column bands of a full brick view are
// lined, half of them with brick on the left half, none on a plain wall.
TEST(VisualSonar, BrickCoursesAreWallLinesAndPlainViewsAreNot) {
  const CameraModel cam = SonarCamera();
  VisualSonar sonar(cam);
  auto brick = [](int brick_to, int period) {
    Image im;
    for (int u = 0; u < im.w; ++u)
      for (int v = 0; v < im.h; ++v)
        im.At(u, v) = u < brick_to ? Noisy(v % period == 0 ? 118.0 : 100.0, u, v) : Noisy(130.0, u, v);
    return im;
  };
  for (const int period : {4, 7, 11}) {
    sonar.Process(brick(64, period).View());
    EXPECT_DOUBLE_EQ(sonar.WallLineFraction(), 1.0) << period;
    sonar.Process(brick(32, period).View());
    EXPECT_DOUBLE_EQ(sonar.WallLineFraction(), 0.5) << period;
  }
  sonar.Process(brick(0, 7).View());
  EXPECT_DOUBLE_EQ(sonar.WallLineFraction(), 0.0);
  // Mortar too faint (a 2-level line under the noise spread's floor): not lined.
  Image faint;
  for (int u = 0; u < faint.w; ++u)
    for (int v = 0; v < faint.h; ++v) faint.At(u, v) = static_cast<std::uint8_t>(v % 7 == 0 ? 102 : 100);
  sonar.Process(faint.View());
  EXPECT_DOUBLE_EQ(sonar.WallLineFraction(), 0.0);
}

// A corridor view (floor brightening smoothly toward the bottom, a wall above its boundary) and a
// single seam across a wall (one line, no period) have no wall lines.
TEST(VisualSonar, FloorGradientAndASingleSeamAreNotWallLines) {
  const CameraModel cam = SonarCamera();
  VisualSonar sonar(cam);
  Image corridor;
  for (int u = 0; u < corridor.w; ++u)
    for (int v = 0; v < corridor.h; ++v) corridor.At(u, v) = v > 26 ? Noisy(120.0 + 3.0 * (v - 26), u, v) : Noisy(80.0, u, v);
  sonar.Process(corridor.View());
  EXPECT_DOUBLE_EQ(sonar.WallLineFraction(), 0.0);
  Image seam;
  for (int u = 0; u < seam.w; ++u)
    for (int v = 0; v < seam.h; ++v) seam.At(u, v) = Noisy(v == 30 ? 125.0 : 100.0, u, v);
  sonar.Process(seam.View());
  EXPECT_DOUBLE_EQ(sonar.WallLineFraction(), 0.0);
}

TEST(VisualSonar, WallLineOptionsAreValidated) {
  VisualSonarOptions o;
  o.wall_line_min_correlation = 0.0;
  EXPECT_NE(o.Validate().find("wall_line_min_correlation"), std::string::npos);
  o = {};
  o.wall_line_max_lag = 2;
  EXPECT_NE(o.Validate().find("wall_line"), std::string::npos);
  o = {};
  o.wall_line_band_columns = 1;
  EXPECT_NE(o.Validate().find("wall_line_band_columns"), std::string::npos);
}

TEST(VisualSonar, BadInputIsAClearError) {
  const CameraModel cam = SonarCamera();
  VisualSonarOptions bad;
  bad.step_threshold = -1.0;
  EXPECT_THROW(VisualSonar(cam, bad), Error);
  CameraModel up = cam;
  up.pitch_deg = 40.0;  // horizon below the frame
  EXPECT_THROW(VisualSonar{up}, Error);
  VisualSonar sonar(cam);
  std::vector<std::uint8_t> small(32 * 24, 0);
  EXPECT_THROW(sonar.Process(GrayView{small.data(), 32, 24, 32}), std::logic_error);  // a programming error
}

// A scan with every column reading a wall `range` ahead along x.
std::vector<SonarColumn> WallScan(const CameraModel& cam, double range_x) {
  std::vector<SonarColumn> scan(static_cast<std::size_t>(cam.width));
  for (int u = 0; u < cam.width; ++u) {
    SonarColumn& c = scan[static_cast<std::size_t>(u)];
    c.bearing_rad = cam.BearingOfColumn(u);
    c.range_m = range_x / std::cos(c.bearing_rad);
    c.kind = SonarReturn::kBoundary;
  }
  return scan;
}

TEST(ObstacleMemory, RememberedWallLimitsFreeTravelAsTheRobotMoves) {
  const CameraModel cam = SonarCamera();
  ObstacleMemory mem;
  const double radius = 0.35;
  mem.Update(WallScan(cam, 2.5), Pose2{0.0, 0.0, 0.0}, 0.0, 1.2);
  mem.Gather(Pose2{0.0, 0.0, 0.0}, 0.0);
  EXPECT_NEAR(mem.FreeTravel(Pose2{0.0, 0.0, 0.0}, 0.0, radius, 5.0), 2.5 - radius, 0.02);
  EXPECT_EQ(mem.FreeTravel(Pose2{0.0, 0.0, 0.0}, kPi / 2, radius, 5.0), 5.0);  // nothing seen to the left
  // The robot drives 1.5 m toward it: the wall is now inside the camera's blind range, but remembered.
  const Pose2 moved{1.5, 0.0, 0.0};
  mem.Gather(moved, 1.0);
  EXPECT_NEAR(mem.FreeTravel(moved, 0.0, radius, 5.0), 1.0 - radius, 0.02);
  // Forgotten after keep_seconds.
  mem.Gather(moved, 1000.0);
  EXPECT_EQ(mem.FreeTravel(moved, 0.0, radius, 5.0), 5.0);
}

TEST(ObstacleMemory, ClearRectRemovesOnlyThePointsInsideTheRectangle) {
  const CameraModel cam = SonarCamera();
  ObstacleMemory mem;
  mem.Update(WallScan(cam, 2.0), Pose2{}, 0.0, 1.2);  // a wall across x = 2 (|y| up to ~1.15)
  mem.Gather(Pose2{}, 0.0);
  const std::size_t before = mem.Gathered().size();
  ASSERT_GT(before, 10u);
  // In a frame at (2, 0) facing +y: s along +y, l toward -x. Clear the wall's part with y > 0.3.
  const int removed = mem.ClearRect(Pose2{2.0, 0.0, kPi / 2}, 0.3, 5.0, -0.2, 0.2);
  mem.Gather(Pose2{}, 0.0);
  EXPECT_EQ(static_cast<std::size_t>(removed), before - mem.Gathered().size());
  EXPECT_GT(removed, 0);
  for (const Eigen::Vector2d& p : mem.Gathered()) EXPECT_LE(p.y(), 0.3 + 1e-9);
  // The rest of the wall still stops the robot straight ahead; nothing outside the rectangle went.
  EXPECT_NEAR(mem.FreeTravel(Pose2{}, 0.0, 0.35, 5.0), 2.0 - 0.35, 0.02);
  EXPECT_EQ(mem.ClearRect(Pose2{2.0, 0.0, kPi / 2}, 0.3, 5.0, -0.2, 0.2), 0);
}

TEST(ObstacleMemory, FloorSeenLaterClearsAStaleBoundary) {
  const CameraModel cam = SonarCamera();
  ObstacleMemory mem;
  mem.Update(WallScan(cam, 2.0), Pose2{}, 0.0, 1.2);
  mem.Update(WallScan(cam, 2.8), Pose2{}, 0.1, 1.2);  // the same view now shows floor to 2.8 m
  mem.Gather(Pose2{}, 0.1);
  EXPECT_NEAR(mem.FreeTravel(Pose2{}, 0.0, 0.35, 5.0), 2.8 - 0.35, 0.02);
}

// The columns that look along a post 3 cm wide, 1.0 m straight ahead.
bool OnPostAhead(const SonarColumn& c) { return std::abs(std::sin(c.bearing_rad) * 1.0) < 0.03; }

// A post remembered 1.0 m ahead; a later scan's median reads floor to a wall at 2.8 m in every
// column, but the columns along the post read it themselves (own_range_m 1.0 m) or were blocked
// near. Without clear_own_within_m the later scan erases the post; with it the post still stops
// the robot, and columns whose own reading agrees with the median clear as before.
TEST(ObstacleMemory, OwnRangeClearingKeepsWhatTheColumnItselfSaw) {
  const CameraModel cam = SonarCamera();
  auto run = [&](double own_within_m, bool blocked) {
    ObstacleMemoryOptions opt;
    opt.clear_own_within_m = own_within_m;
    ObstacleMemory mem(opt);
    std::vector<SonarColumn> first = WallScan(cam, 2.8);
    for (SonarColumn& c : first) {
      c.own_range_m = c.range_m;
      if (OnPostAhead(c)) c.range_m = c.own_range_m = 1.0 / std::cos(c.bearing_rad);
    }
    mem.Update(first, Pose2{}, 0.0, 0.6);
    std::vector<SonarColumn> later = WallScan(cam, 2.8);
    for (SonarColumn& c : later) {
      c.own_range_m = c.range_m;
      if (OnPostAhead(c)) c.own_range_m = blocked ? 0.0 : 1.0 / std::cos(c.bearing_rad);
    }
    mem.Update(later, Pose2{}, 0.1, 0.6);
    mem.Gather(Pose2{}, 0.1);
    return mem.FreeTravel(Pose2{}, 0.0, 0.25, 5.0);
  };
  EXPECT_NEAR(run(0.0, false), 2.8 - 0.25, 0.02);  // the post is erased
  EXPECT_NEAR(run(1.2, false), 1.0 - 0.25, 0.02);
  EXPECT_NEAR(run(1.2, true), 1.0 - 0.25, 0.02);
  EXPECT_NEAR(run(0.8, false), 2.8 - 0.25, 0.02);  // own readings beyond the option's range do not hold
  ObstacleMemoryOptions bad;
  bad.clear_own_within_m = -1.0;
  EXPECT_NE(bad.Validate(), "");
}

// The same post with clear_own_driving_only: what the columns' own readings keep serves driving
// only. The disc's free travel (FreeTravel with kept_edges) stops at the post; the judgements'
// queries (FreeTravel without kept_edges, PointsFreeTravel, the gathered points, PointsInRect)
// see the later scan's floor as without own-range clearing. A later scan whose columns' own
// readings reach the wall clears the post for every query.
TEST(ObstacleMemory, OwnRangeDrivingOnlyKeepsThePostForTheDiscAlone) {
  const CameraModel cam = SonarCamera();
  ObstacleMemoryOptions opt;
  opt.clear_own_within_m = 1.2;
  opt.clear_own_driving_only = true;
  ObstacleMemory mem(opt);
  std::vector<SonarColumn> first = WallScan(cam, 2.8);
  int post_columns = 0;
  for (SonarColumn& c : first) {
    c.own_range_m = c.range_m;
    if (OnPostAhead(c)) c.range_m = c.own_range_m = 1.0 / std::cos(c.bearing_rad), ++post_columns;
  }
  ASSERT_GE(post_columns, 1);
  mem.Update(first, Pose2{}, 0.0, 0.6);
  mem.Gather(Pose2{}, 0.0);
  EXPECT_NEAR(mem.PointsFreeTravel(Pose2{}, 0.0, 0.25, 5.0), 1.0 - 0.25, 0.02);  // seen: every query has it
  for (const bool blocked : {false, true}) {
    ObstacleMemory m = mem;
    std::vector<SonarColumn> later = WallScan(cam, 2.8);
    for (SonarColumn& c : later) c.own_range_m = OnPostAhead(c) ? (blocked ? 0.0 : 1.0 / std::cos(c.bearing_rad)) : c.range_m;
    m.Update(later, Pose2{}, 0.1, 0.6);
    m.Gather(Pose2{}, 0.1);
    EXPECT_NEAR(m.FreeTravel(Pose2{}, 0.0, 0.25, 5.0), 1.0 - 0.25, 0.02) << blocked;
    EXPECT_NEAR(m.FreeTravel(Pose2{}, 0.0, 0.25, 5.0, true, true, 0.0, 0.0, false), 2.8 - 0.25, 0.02) << blocked;
    EXPECT_NEAR(m.PointsFreeTravel(Pose2{}, 0.0, 0.25, 5.0), 2.8 - 0.25, 0.02) << blocked;
    EXPECT_NEAR(m.PointsFreeTravel(Pose2{}, 0.0, 0.25, 5.0, 0.0, 0.0, true), 1.0 - 0.25, 0.02) << blocked;
    for (const Eigen::Vector2d& p : m.Gathered()) EXPECT_GT(p.x(), 2.0) << blocked;
    std::vector<Eigen::Vector2d> in_rect;
    m.PointsInRect(Pose2{}, 0.5, 1.5, -0.3, 0.3, 0.1, &in_rect);
    EXPECT_TRUE(in_rect.empty()) << blocked;
    // The columns' own readings now reach the wall: the post is gone for driving too.
    std::vector<SonarColumn> clear = WallScan(cam, 2.8);
    for (SonarColumn& c : clear) c.own_range_m = c.range_m;
    m.Update(clear, Pose2{}, 0.2, 0.6);
    m.Gather(Pose2{}, 0.2);
    EXPECT_NEAR(m.FreeTravel(Pose2{}, 0.0, 0.25, 5.0), 2.8 - 0.25, 0.02) << blocked;
  }
}

TEST(ObstacleMemory, WallSeenFromSeveralPositionsSurvivesAReflectionOfFloorBeyondIt) {
  // A scripted walk toward a mirror wall at x = 4: its base is seen from x = 0, 0.2, ..., 1.4 m
  // (8 scans, the same cells each time), then, nearer, the mirror shows the floor continuing to 6 m.
  const CameraModel cam = SonarCamera();
  const ObstacleMemoryOptions defaults;
  ASSERT_EQ(defaults.confirm_scans, 0);  // off by default (see the header)
  ASSERT_EQ(defaults.confirm_baseline_m, 1.0);
  const double radius = 0.35;
  const Pose2 near{2.0, 0.0, 0.0};
  auto walk = [&](ObstacleMemory& mem, int scans, double spacing) {
    for (int i = 0; i < scans; ++i) mem.Update(WallScan(cam, 4.0 - spacing * i), Pose2{spacing * i, 0.0, 0.0}, 0.1 * i, 1.2);
    mem.Update(WallScan(cam, 6.0), near, 1.0, 1.2);
    mem.Gather(near, 1.0);
    return mem.FreeTravel(near, 0.0, radius, 5.0);
  };
  ObstacleMemoryOptions on;
  on.confirm_scans = 8;
  ObstacleMemory mem(on);
  EXPECT_NEAR(walk(mem, 8, 0.2), 2.0 - radius, 0.02);  // the wall stays
  // Seen by fewer scans, or with confirmation off, the later floor removes it.
  ObstacleMemory few(on);
  EXPECT_EQ(walk(few, 7, 0.2), 5.0);
  ObstacleMemory unconfirmed(defaults);
  EXPECT_EQ(walk(unconfirmed, 8, 0.2), 5.0);
  // Eight scans from (nearly) one position are not a baseline: not confirmed.
  ObstacleMemory still(on);
  EXPECT_EQ(walk(still, 8, 0.1), 5.0);
}

TEST(ObstacleMemory, BlockedNearStopsForwardTravelUnlessTheFloorThereWasSeen) {
  const CameraModel cam = SonarCamera();
  std::vector<SonarColumn> blocked = WallScan(cam, 2.0);
  for (SonarColumn& c : blocked) {
    c.kind = SonarReturn::kBlockedNear;
    c.range_m = 0.0;
  }
  ObstacleMemory mem;
  mem.Update(blocked, Pose2{}, 0.0, 1.2);
  mem.Gather(Pose2{}, 0.0);
  EXPECT_EQ(mem.FreeTravel(Pose2{}, 0.0, 0.35, 5.0), 0.0);
  EXPECT_EQ(mem.FreeTravel(Pose2{}, 0.0, 0.35, 5.0, /*use_blocked=*/false), 0.0);  // nothing seen there
  EXPECT_EQ(mem.FreeTravel(Pose2{}, kPi, 0.35, 5.0), 5.0);  // behind: not blocked by this scan
  // Seen from 2 m back: floor up to 3.3 m ahead of that pose (1.3 m ahead of the robot now,
  // beyond the blind zone checked from here).
  ObstacleMemory seen;
  seen.Update(WallScan(cam, 3.3), Pose2{-2.0, 0.0, 0.0}, 0.0, 1.2);
  seen.Update(blocked, Pose2{}, 1.0, 1.2);
  seen.Gather(Pose2{}, 1.0);
  EXPECT_EQ(seen.FreeTravel(Pose2{}, 0.0, 0.35, 5.0), 0.0);
  EXPECT_NEAR(seen.FreeTravel(Pose2{}, 0.0, 0.35, 5.0, /*use_blocked=*/false), 1.3 - 0.35, 0.05);
  // The robot turned since that floor was seen (seen_free_exempts false): the blockage counts.
  EXPECT_EQ(seen.FreeTravel(Pose2{}, 0.0, 0.35, 5.0, false, /*seen_free_exempts=*/false), 0.0);
}

// One column blocked near, straight ahead: the thing may stand anywhere from the disc to the blind
// range, and the directions it closes are those whose swept band (radius r) meets its ray at
// blocked_min_range_m, a sector of half-width asin(r / blocked_min_range_m): 35.7 degrees at 0.6 m
// and 51.1 degrees at 0.45 m for r = 0.35. A thing 0.36 m away (the obstacle course's column of
// seed 4's start 1) is met by the disc along any heading within 49 degrees of it.
TEST(ObstacleMemory, BlockedSectorWidensAsTheThingMayStandNearer) {
  const CameraModel cam = SonarCamera();
  std::vector<SonarColumn> scan = WallScan(cam, 2.0);
  std::size_t ahead = 0;
  for (std::size_t i = 0; i < scan.size(); ++i)
    if (std::abs(scan[i].bearing_rad) < std::abs(scan[ahead].bearing_rad)) ahead = i;
  ASSERT_LT(std::abs(scan[ahead].bearing_rad), 0.02);
  scan[ahead].kind = SonarReturn::kBlockedNear;
  scan[ahead].range_m = 0.0;
  const double r = 0.35;
  const double deg = kPi / 180.0;
  // query_m > 0: the query's own range (the explorer's settled_ or setoff_blocked_min_range_m).
  auto free_along = [&](double min_range_m, double yaw, double query_m = 0.0) {
    ObstacleMemoryOptions opt;
    opt.blocked_min_range_m = min_range_m;
    opt.blind_points_from_m = 0.0;  // the sector alone
    ObstacleMemory mem(opt);
    mem.Update(scan, Pose2{}, 0.0, 0.6);
    mem.Gather(Pose2{}, 0.0);
    return mem.FreeTravel(Pose2{}, yaw, r, 5.0, true, true, query_m);
  };
  const double b = scan[ahead].bearing_rad;
  for (const double side : {1.0, -1.0}) {
    // 0.6 m: closed within 35.7 degrees of the column, open beyond.
    EXPECT_EQ(free_along(0.6, b + side * 34.0 * deg), 0.0);
    EXPECT_EQ(free_along(0.6, b + side * 40.0 * deg), 5.0);
    // 0.45 m: 40 degrees off is closed now, 53 degrees open.
    EXPECT_EQ(free_along(0.45, b + side * 40.0 * deg), 0.0);
    EXPECT_EQ(free_along(0.45, b + side * 50.0 * deg), 0.0);
    EXPECT_EQ(free_along(0.45, b + side * 53.0 * deg), 5.0);
  }
  // A query's own range replaces the option's: 0.45 m set, 0.6 m asked.
  EXPECT_EQ(free_along(0.45, b + 40.0 * deg, 0.6), 5.0);
  EXPECT_EQ(free_along(0.45, b + 34.0 * deg, 0.6), 0.0);
  // Nearer than the disc's radius: every heading toward the thing's half-plane is closed.
  EXPECT_EQ(free_along(0.3, b + 89.0 * deg), 0.0);
  EXPECT_EQ(free_along(0.3, b + 91.0 * deg), 5.0);
  ObstacleMemoryOptions bad;
  bad.blocked_min_range_m = 0.0;
  EXPECT_FALSE(bad.Validate().empty());
}

// A chair leg flickers: blocked near in one scan (columns a few degrees right of the heading), the
// next scan reads floor beyond it in every column. With blocked_hold_s the first scan's blockage
// still stops travel along those columns (from where it was taken) until the hold has passed; a
// direction clear of its columns is free; without the hold the latest scan alone decides. Then
// the hold's conditions: enough columns, enough scans, and use_blocked.
// Runs of blocked-near columns: an edge of a near thing unless a neighbour of the run (on either
// side, where the view has one) is a floor step nearer than the limit.
TEST(ObstacleMemory, NearEdgeRunsEndInFloorRunningFar) {
  using K = SonarReturn;
  auto scan = [](const std::vector<std::pair<K, double>>& cols) {
    std::vector<SonarColumn> s;
    for (const auto& [kind, range] : cols) {
      SonarColumn c;
      c.kind = kind;
      c.range_m = range;
      s.push_back(c);
    }
    return s;
  };
  using V = std::vector<char>;
  // A run at the view's edge beside floor running far, and one between far floor and nothing
  // floor-like: both edges.
  EXPECT_EQ(ObstacleMemory::NearEdgeRuns(scan({{K::kBlockedNear, 0}, {K::kBlockedNear, 0}, {K::kFar, 6},
                                               {K::kUnknown, 6}, {K::kBlockedNear, 0}, {K::kFar, 6}}), 1.8),
            (V{1, 1, 0, 0, 1, 0}));
  // Beside a step at 1.57 m (under 1.8): a wall running on; at 2.5 m: an edge.
  EXPECT_EQ(ObstacleMemory::NearEdgeRuns(scan({{K::kBlockedNear, 0}, {K::kBlockedNear, 0}, {K::kBoundary, 1.57},
                                               {K::kBoundary, 2.5}, {K::kBlockedNear, 0}}), 1.8),
            (V{0, 0, 0, 0, 1}));
  // A step near on one side is enough; a whole view blocked is an edge (no neighbour shows a step).
  EXPECT_EQ(ObstacleMemory::NearEdgeRuns(scan({{K::kFar, 6}, {K::kBlockedNear, 0}, {K::kBoundary, 1.0}}), 1.8),
            (V{0, 0, 0}));
  EXPECT_EQ(ObstacleMemory::NearEdgeRuns(scan({{K::kBlockedNear, 0}, {K::kBlockedNear, 0}}), 1.8), (V{1, 1}));
  EXPECT_TRUE(ObstacleMemory::NearEdgeRuns({}, 1.8).empty());
  ObstacleMemoryOptions bad;
  bad.blocked_edge_step_m = -0.1;
  EXPECT_NE(bad.Validate(), "");
}

TEST(ObstacleMemory, HeldBlockageOutlivesTheNextScanUntilTheHoldPasses) {
  const CameraModel cam = SonarCamera();
  // The leg's columns (-8 to -4 degrees) blocked near in a scan of a wall wall_m ahead.
  auto leg_before = [&](double wall_m) {
    std::vector<SonarColumn> scan = WallScan(cam, wall_m);
    for (SonarColumn& c : scan) {
      const double deg = c.bearing_rad * 180.0 / kPi;
      if (deg > -8.0 && deg < -4.0) {
        c.kind = SonarReturn::kBlockedNear;
        c.range_m = 0.0;
      }
    }
    return scan;
  };
  const std::vector<SonarColumn> leg = leg_before(2.0);
  auto run = [&](double hold_s, const Pose2& at, double query_s, double yaw) {
    ObstacleMemoryOptions opt;
    opt.blocked_hold_s = hold_s;
    ObstacleMemory mem(opt);
    mem.Update(leg, Pose2{}, 0.0, 0.6);
    mem.Update(WallScan(cam, 2.0), at, query_s, 0.6);  // floor to the wall in every column
    mem.Gather(at, query_s);
    return mem.FreeTravel(at, yaw, 0.3, 5.0);
  };
  const Pose2 ahead{0.1, 0.0, 0.0};
  EXPECT_NEAR(run(0.0, ahead, 0.1, 0.0), 1.9 - 0.3, 0.02);  // latest scan only: free to the wall
  EXPECT_EQ(run(0.5, ahead, 0.1, 0.0), 0.0);                // held: no travel past where it was seen
  EXPECT_EQ(run(0.5, Pose2{}, 0.1, 0.0), 0.0);
  EXPECT_NEAR(run(0.5, ahead, 0.6, 0.0), 1.9 - 0.3, 0.02);  // the hold has passed
  // 60 degrees left of the leg's columns: outside their sector (asin(0.3 / 0.6) = 30 degrees).
  EXPECT_NEAR(run(0.5, ahead, 0.1, 55.0 * kPi / 180.0), run(0.0, ahead, 0.1, 55.0 * kPi / 180.0), 1e-12);
  // A blockage narrower than blocked_hold_min_columns is not held (a carpet's single columns).
  std::vector<SonarColumn> narrow = WallScan(cam, 2.0);
  int n_narrow = 0;
  for (SonarColumn& c : narrow) {
    const double deg = c.bearing_rad * 180.0 / kPi;
    if (deg > -6.0 && deg < -4.0) {
      c.kind = SonarReturn::kBlockedNear;
      c.range_m = 0.0;
      ++n_narrow;
    }
  }
  ASSERT_GT(n_narrow, 0);
  ASSERT_LT(n_narrow, ObstacleMemoryOptions{}.blocked_hold_min_columns);
  {
    ObstacleMemory mem;  // the defaults: held for 0.5 s
    mem.Update(narrow, Pose2{}, 0.0, 0.6);
    mem.Update(WallScan(cam, 2.0), ahead, 0.1, 0.6);
    mem.Gather(ahead, 0.1);
    EXPECT_NEAR(mem.FreeTravel(ahead, 0.0, 0.3, 5.0), 1.9 - 0.3, 0.02);
  }
  // blocked_hold_scans 2: one held scan alone does not count; two within the hold do.
  auto scans = [&](int blocked_scans) {
    ObstacleMemoryOptions opt;
    opt.blocked_hold_scans = 2;
    ObstacleMemory mem(opt);
    for (int i = 0; i < blocked_scans; ++i) mem.Update(leg, Pose2{}, 0.1 * i, 0.6);
    mem.Update(WallScan(cam, 2.0), ahead, 0.1 * blocked_scans, 0.6);
    mem.Gather(ahead, 0.1 * blocked_scans);
    return mem.FreeTravel(ahead, 0.0, 0.3, 5.0);
  };
  EXPECT_NEAR(scans(1), 1.9 - 0.3, 0.02);
  EXPECT_EQ(scans(2), 0.0);
  // Held blockages count only where the blocked columns count in full (use_blocked).
  {
    ObstacleMemory mem;
    mem.Update(leg, Pose2{}, 0.0, 0.6);
    mem.Update(WallScan(cam, 2.0), ahead, 0.1, 0.6);
    mem.Gather(ahead, 0.1);
    EXPECT_NEAR(mem.FreeTravel(ahead, 0.0, 0.3, 5.0, /*use_blocked=*/false), 1.9 - 0.3, 0.02);
  }
  // The robot turned 40 degrees left where it stands: the leg's columns (-8 to -4 degrees) have
  // left the view (10 to 70 degrees). Along 20 degrees, inside their sector, they hold it only
  // with blocked_hold_in_view off; on, the latest scan alone decides.
  auto turned = [&](double hold_s, bool in_view, double turn_deg, double along_deg) {
    ObstacleMemoryOptions opt;
    opt.blocked_hold_s = hold_s;
    opt.blocked_hold_in_view = in_view;
    ObstacleMemory mem(opt);
    const Pose2 left{0.0, 0.0, turn_deg * kPi / 180.0};
    mem.Update(leg, Pose2{}, 0.0, 0.6);
    mem.Update(WallScan(cam, 2.0), left, 0.1, 0.6);
    mem.Gather(left, 0.1);
    return mem.FreeTravel(left, along_deg * kPi / 180.0, 0.3, 5.0);
  };
  ASSERT_GT(turned(0.0, true, 40.0, 20.0), 0.5);
  EXPECT_EQ(turned(0.5, false, 40.0, 20.0), 0.0);
  EXPECT_NEAR(turned(0.5, true, 40.0, 20.0), turned(0.0, true, 40.0, 20.0), 1e-12);
  // Turned only 10 degrees (the view -20 to 40 degrees): the leg is still in view and held.
  EXPECT_EQ(turned(0.5, true, 10.0, 0.0), 0.0);
  // A query's standing_m: where the robot still stands (within standing_m of where the held scan
  // was taken) the held columns of a near thing's edge count out of the view too (the leg's run
  // has the wall 2 m away beside it, beyond the 0.6 m blind range plus blocked_edge_step_m);
  // moved 5 cm away, they do not.
  auto standing = [&](const Pose2& at, double standing_m, const std::vector<SonarColumn>& seen = {}) {
    ObstacleMemory mem;  // the defaults: held for 0.5 s, in view only
    mem.Update(seen.empty() ? leg : seen, Pose2{}, 0.0, 0.6);
    mem.Update(WallScan(cam, 2.0), at, 0.1, 0.6);
    mem.Gather(at, 0.1);
    return mem.FreeTravel(at, 20.0 * kPi / 180.0, 0.3, 5.0, /*use_blocked=*/true, /*seen_free_exempts=*/true,
                          /*min_range_m=*/0.0, standing_m);
  };
  const Pose2 left40{0.0, 0.0, 40.0 * kPi / 180.0};
  ASSERT_GT(standing(left40, 0.0), 0.5);
  EXPECT_EQ(standing(left40, 0.02), 0.0);
  EXPECT_EQ(standing(Pose2{0.01, 0.01, 40.0 * kPi / 180.0}, 0.02), 0.0);
  const Pose2 moved{-0.05, 0.0, 40.0 * kPi / 180.0};
  EXPECT_NEAR(standing(moved, 0.02), standing(moved, 0.0), 1e-12);
  EXPECT_GT(standing(moved, 0.02), 0.5);
  // The same columns blocked beside a floor step 0.9 m away (a wall running on into the blind
  // zone, not an edge): out of the view, standing or not, they hold nothing.
  const std::vector<SonarColumn> wall_on = leg_before(0.9);
  EXPECT_GT(standing(left40, 0.02, wall_on), 0.5);
  EXPECT_NEAR(standing(left40, 0.02, wall_on), standing(left40, 0.0, wall_on), 1e-12);
  ObstacleMemoryOptions bad;
  bad.blocked_hold_s = -0.1;
  EXPECT_NE(bad.Validate(), "");
  bad = ObstacleMemoryOptions{};
  bad.blocked_hold_min_columns = 0;
  EXPECT_NE(bad.Validate(), "");
  bad = ObstacleMemoryOptions{};
  bad.blocked_hold_scans = 0;
  EXPECT_NE(bad.Validate(), "");
}

// A wall filling the view on blocked_view_scans consecutive scans stops forward travel even where
// the floor in the blind zone was seen from farther back (a wall with the floor's grey lets the
// sonar "see" floor through it); a single such scan does not (a view without floor contrast).
// Two walls 2 m apart along direction theta, seen from between them in one scan (a column per
// remembered point): the memory's wall axis is theta modulo 90 degrees, strongly; scattered points
// give no direction.
// A scan with one boundary column at each point (robot frame: x ahead, y left).
std::vector<SonarColumn> ScanOfPoints(const std::vector<Eigen::Vector2d>& pts) {
  std::vector<SonarColumn> scan;
  for (const Eigen::Vector2d& q : pts) {
    SonarColumn c;
    c.kind = SonarReturn::kBoundary;
    c.bearing_rad = std::atan2(q.y(), q.x());
    c.range_m = q.norm();
    scan.push_back(c);
  }
  return scan;
}

// Walls 1.0 m to each side of the axis (a point every 0.05 m along), and one stray point 0.77 m to
// the right, abeam (0.23 m from the nearest wall point): the nearest point reads it; with a
// cluster distance of 0.15 m a side's wall is the nearest point with another within that distance
// of it. A side with one point only has no wall then.
TEST(ObstacleMemory, SideDistancesWithAClusterSkipAStrayPoint) {
  std::vector<Eigen::Vector2d> pts;
  for (double x = -1.0; x <= 1.0; x += 0.05) {
    pts.emplace_back(x, 1.0);
    pts.emplace_back(x, -1.0);
  }
  pts.emplace_back(0.1, -0.77);
  ObstacleMemory mem;
  mem.Update(ScanOfPoints(pts), Pose2{}, 0.0, 1.2);
  mem.Gather(Pose2{}, 0.1);
  double left = 0.0, right = 0.0;
  mem.SideDistances(Pose2{}, 0.0, 0.3, 1.8, &left, &right);
  EXPECT_NEAR(left, 1.0, 0.06);
  EXPECT_NEAR(right, 0.77, 0.06);
  mem.SideDistances(Pose2{}, 0.0, 0.3, 1.8, &left, &right, 0.15);
  EXPECT_NEAR(left, 1.0, 0.06);
  EXPECT_NEAR(right, 1.0, 0.06);
  // One point alone on the right, nothing on the left.
  ObstacleMemory one;
  one.Update(ScanOfPoints({Eigen::Vector2d(0.0, -0.8)}), Pose2{}, 0.0, 1.2);
  one.Gather(Pose2{}, 0.1);
  one.SideDistances(Pose2{}, 0.0, 0.3, 1.8, &left, &right);
  EXPECT_EQ(left, -1.0);
  EXPECT_NEAR(right, 0.8, 0.06);
  one.SideDistances(Pose2{}, 0.0, 0.3, 1.8, &left, &right, 0.15);
  EXPECT_EQ(left, -1.0);
  EXPECT_EQ(right, -1.0);  // one point is no wall
}

TEST(ObstacleMemory, WallAxisIsTheRememberedWallsDirectionModulo90) {
  for (const double theta_deg : {20.0, 70.0, -30.0}) {
    const double t = DegToRad(theta_deg);
    std::vector<Eigen::Vector2d> pts;
    for (double x = -1.5; x <= 1.5; x += 0.1)
      for (const double side : {-1.0, 1.0})
        pts.emplace_back(std::cos(t) * x - std::sin(t) * side, std::sin(t) * x + std::cos(t) * side);
    ObstacleMemory mem;
    mem.Update(ScanOfPoints(pts), Pose2{}, 0.0, 1.2);
    mem.Gather(Pose2{}, 0.1);
    double strength = 0.0;
    int pairs = 0;
    const double axis = RadToDeg(mem.WallAxisMod90(&strength, &pairs));
    const double expected = std::remainder(theta_deg, 90.0);  // 20, -20, -30
    EXPECT_NEAR(axis, expected, 2.0) << theta_deg;
    EXPECT_GT(strength, 0.8) << theta_deg;
    EXPECT_GE(pairs, 40) << theta_deg;
  }
  // Scattered points (a fixed pseudo-random layout): no direction.
  std::vector<Eigen::Vector2d> pts;
  unsigned s = 12345u;
  auto next = [&s] {
    s = s * 1103515245u + 12345u;
    return static_cast<double>((s >> 8) & 0xFFFF) / 65535.0;
  };
  for (int i = 0; i < 120; ++i) pts.emplace_back(-2.0 + 4.0 * next(), -2.0 + 4.0 * next());
  ObstacleMemory mem;
  mem.Update(ScanOfPoints(pts), Pose2{}, 0.0, 1.2);
  mem.Gather(Pose2{}, 0.1);
  double strength = 0.0;
  int pairs = 0;
  mem.WallAxisMod90(&strength, &pairs);
  EXPECT_LT(strength, 0.4);
}

TEST(ObstacleMemory, WallFillingTheViewOnConsecutiveScansStopsDespiteFloorSeen) {
  const CameraModel cam = SonarCamera();
  std::vector<SonarColumn> blocked = WallScan(cam, 2.0);
  for (SonarColumn& c : blocked) {
    c.kind = SonarReturn::kBlockedNear;
    c.range_m = 0.0;
  }
  const int need = ObstacleMemoryOptions{}.blocked_view_scans;
  ASSERT_GE(need, 2);
  for (int scans = 1; scans <= need; ++scans) {
    ObstacleMemory mem;
    mem.Update(WallScan(cam, 3.3), Pose2{-2.0, 0.0, 0.0}, 0.0, 1.2);  // floor seen to 1.3 m ahead of the pose below
    for (int k = 0; k < scans; ++k) mem.Update(blocked, Pose2{}, 1.0 + 0.1 * k, 1.2);
    mem.Gather(Pose2{}, 1.0 + 0.1 * scans);
    const double free = mem.FreeTravel(Pose2{}, 0.0, 0.35, 5.0, /*use_blocked=*/false);
    if (scans < need) EXPECT_NEAR(free, 1.3 - 0.35, 0.05) << scans << " scans";
    else EXPECT_EQ(free, 0.0) << scans << " scans";
  }
  // Fewer blocked columns than blocked_view_fraction: the floor seen still counts.
  std::vector<SonarColumn> half = WallScan(cam, 3.3);
  for (std::size_t i = 0; i < half.size(); ++i)
    if (i % 2 == 0) {
      half[i].kind = SonarReturn::kBlockedNear;
      half[i].range_m = 0.0;
    }
  ObstacleMemory mem;
  mem.Update(WallScan(cam, 3.3), Pose2{-2.0, 0.0, 0.0}, 0.0, 1.2);
  for (int k = 0; k < need + 2; ++k) mem.Update(half, Pose2{}, 1.0 + 0.1 * k, 1.2);
  mem.Gather(Pose2{}, 2.0);
  EXPECT_GT(mem.FreeTravel(Pose2{}, 0.0, 0.35, 5.0, /*use_blocked=*/false), 0.9);
  // Off: as before, the floor seen counts.
  ObstacleMemoryOptions off;
  off.blocked_view_fraction = 0.0;
  ObstacleMemory old(off);
  old.Update(WallScan(cam, 3.3), Pose2{-2.0, 0.0, 0.0}, 0.0, 1.2);
  for (int k = 0; k < need + 2; ++k) old.Update(blocked, Pose2{}, 1.0 + 0.1 * k, 1.2);
  old.Gather(Pose2{}, 2.0);
  EXPECT_NEAR(old.FreeTravel(Pose2{}, 0.0, 0.35, 5.0, /*use_blocked=*/false), 1.3 - 0.35, 0.05);
}

// The explorer's blind views (a corridor in the glance, no floor contrast in the sonar) clear what
// the memory holds along their rays out to the blind range, and only there; no floor is marked
// seen, so a later blockage still counts in full.
TEST(ObstacleMemory, UnknownRaysClearOnlyWithinTheirRangeAndMarkNoFloor) {
  const CameraModel cam = SonarCamera();
  ObstacleMemory two;
  two.Update(WallScan(cam, 2.0), Pose2{-1.0, 0.0, 0.0}, 0.0, 1.2);  // a "wall" at x = 1.0
  two.Gather(Pose2{}, 0.1);
  ASSERT_NEAR(two.FreeTravel(Pose2{}, 0.0, 0.35, 5.0), 1.0 - 0.35, 0.05);
  std::vector<SonarColumn> unknown = WallScan(cam, 2.0);
  for (SonarColumn& c : unknown) c.kind = SonarReturn::kUnknown;
  two.ClearUnknownRays(unknown, Pose2{}, 1.2);
  two.Gather(Pose2{}, 0.1);
  EXPECT_EQ(two.FreeTravel(Pose2{}, 0.0, 0.35, 5.0), 5.0);
  // Beyond the range: kept.
  ObstacleMemory far;
  far.Update(WallScan(cam, 3.0), Pose2{-1.0, 0.0, 0.0}, 0.0, 1.2);  // x = 2.0
  far.ClearUnknownRays(unknown, Pose2{}, 1.2);
  far.Gather(Pose2{}, 0.1);
  EXPECT_NEAR(far.FreeTravel(Pose2{}, 0.0, 0.35, 5.0), 2.0 - 0.35, 0.05);
  // No floor marked seen: a blocked view right after still stops, even with use_blocked = false.
  std::vector<SonarColumn> blocked = WallScan(cam, 2.0);
  for (SonarColumn& c : blocked) {
    c.kind = SonarReturn::kBlockedNear;
    c.range_m = 0.0;
  }
  two.Update(blocked, Pose2{}, 0.2, 1.2);
  two.Gather(Pose2{}, 0.2);
  EXPECT_EQ(two.FreeTravel(Pose2{}, 0.0, 0.35, 5.0, /*use_blocked=*/false), 0.0);
}

// A corner seen blocked near on the right, then out of view after the robot turned left: the
// soft points along the blocked rays keep it known; without them the way right looks free.
TEST(ObstacleMemory, BlindZoneCornerStaysKnownAfterTurningAway) {
  const CameraModel cam = SonarCamera();
  std::vector<SonarColumn> first = WallScan(cam, 3.0);
  int n_blocked = 0;
  for (SonarColumn& c : first) {
    if (c.bearing_rad > -0.1) continue;
    c.kind = SonarReturn::kBlockedNear;
    c.range_m = 0.0;
    ++n_blocked;
  }
  ASSERT_GT(n_blocked, 10);
  const Pose2 turned{0.0, 0.0, 0.9};  // 52 degrees left: the blocked rays are out of view
  const double right = -0.3;          // a heading into the blocked sector
  // The soft points alone: the blocked-near columns held over the next scan (blocked_hold_s) off,
  // and every soft point kept blind_points_keep_s (a run ending in floor running far beside it is
  // a near thing's edge, kept blind_points_edge_keep_s by default: the next test).
  ObstacleMemoryOptions on;
  on.blocked_hold_s = 0.0;
  on.blind_points_edge_keep_s = 0.0;
  ObstacleMemoryOptions off = on;
  off.blind_points_from_m = 0.0;
  for (const bool soft : {true, false}) {
    ObstacleMemory mem(soft ? on : off);
    mem.Update(first, Pose2{}, 0.0, 1.2);
    mem.Update(WallScan(cam, 2.5), turned, 0.5, 1.2);
    mem.Gather(turned, 0.5);
    const double free = mem.FreeTravel(turned, right, 0.35, 5.0);
    if (soft) {
      // Nearest soft point: 0.6 m along the blocked ray nearest to the heading (bearing -0.1),
      // 0.06 m beside the heading: the disc meets it about 0.35 m earlier.
      EXPECT_LT(free, 0.3);
      // Forgotten after blind_points_keep_s; a heading away from the blocked rays stays free.
      EXPECT_NEAR(mem.FreeTravel(turned, 0.9, 0.35, 5.0), 2.5 - 0.35, 0.05);
      mem.Gather(turned, 0.5 + ObstacleMemoryOptions{}.blind_points_keep_s + 1.0);
      EXPECT_EQ(mem.FreeTravel(turned, right, 0.35, 5.0), 5.0);
    } else {
      EXPECT_EQ(free, 5.0);  // the latest scan saw nothing blocked: the corner is forgotten
    }
  }
}

// A look around in place at the explorer's scan rate (tests below): `first_view` at the start
// pose, then turning left every half second a view of walls 2.5 m away until the view comes round
// to the first view's blocked rays on the right (bearings -0.48 to -0.1 rad), then the alignment
// back to the start's heading; the memory gathered at the set-off, 13.6 s after the first view.
ObstacleMemory LookAround(const ObstacleMemoryOptions& options, const std::vector<SonarColumn>& first_view) {
  const CameraModel cam = SonarCamera();
  const double blind = 1.2;
  const double rate = ExplorerOptions{}.scan_rate_rps;
  const double turn_s = 2.0 * kPi / rate;  // 10.5 s at 0.6 rad/s
  ObstacleMemory mem(options);
  mem.Update(first_view, Pose2{}, 0.0, blind);
  const double half_view = std::abs(cam.BearingOfColumn(0));
  double t = 0.5;
  for (; rate * t + half_view < 2.0 * kPi - 0.5; t += 0.5)
    mem.Update(WallScan(cam, 2.5), Pose2{0.0, 0.0, WrapPi(rate * t)}, t, blind);
  EXPECT_GT(t, 0.7 * turn_s);
  mem.Gather(Pose2{}, turn_s + 3.1);
  return mem;
}

// The first view of the look around: walls `beside_m` away, its columns on the right (bearing
// below -0.1 rad) blocked near.
std::vector<SonarColumn> BlockedOnTheRight(double beside_m) {
  std::vector<SonarColumn> scan = WallScan(SonarCamera(), beside_m);
  for (SonarColumn& c : scan) {
    if (c.bearing_rad > -0.1) continue;
    c.kind = SonarReturn::kBlockedNear;
    c.range_m = 0.0;
  }
  return scan;
}

// The same first view without its blocked columns: as if nothing had been seen there.
std::vector<SonarColumn> Unblocked(std::vector<SonarColumn> view) {
  std::erase_if(view, [](const SonarColumn& c) { return c.kind == SonarReturn::kBlockedNear; });
  return view;
}

// The same corner seen at the start of a look around in place (a full turn at the explorer's scan
// rate, then the alignment back): its blocked-near run ends in floor running far, a near thing's
// edge, so with blind_points_edge_keep_s = 15 its soft points outlast the turn and the heading
// toward it is still closed when the robot sets off (the default since session 39). With the 5 s
// every other soft point is kept, they are forgotten half way round (corridor-7, start 4 of seed 98: set off toward an L's convex corner seen in the
// first half of the scan, and met it). A run beside a floor step near the blind range (a wall
// running on into the blind zone, its base just beyond) or one filling the view (a narrow
// corridor's side wall during the turn) is a guess along a wall, kept 5 s only: kept longer, such
// guesses held robots still in corridor-1's narrow cross corridor.
TEST(ObstacleMemory, BlindZoneCornerOutlastsALookAround) {
  const double blind = 1.2;
  const std::vector<SonarColumn> corner = BlockedOnTheRight(3.0);  // floor 3 m out beside the run
  const std::vector<SonarColumn> wall = BlockedOnTheRight(1.4);    // a step 0.2 m beyond the blind range
  std::vector<SonarColumn> filling = corner;                       // a wall filling the view
  for (SonarColumn& c : filling) {
    c.kind = SonarReturn::kBlockedNear;
    c.range_m = 0.0;
  }
  const double within = blind + ObstacleMemoryOptions{}.blocked_edge_step_m;
  ASSERT_EQ(ObstacleMemory::NearEdgeRuns(corner, within, /*floor_beside=*/true).back(), 1);
  ASSERT_EQ(ObstacleMemory::NearEdgeRuns(wall, within, true).back(), 0);
  // A run with no neighbour is a near thing's edge for the held blockages, not for the soft points.
  ASSERT_EQ(ObstacleMemory::NearEdgeRuns(filling, within).back(), 1);
  ASSERT_EQ(ObstacleMemory::NearEdgeRuns(filling, within, true).back(), 0);
  const double right = -0.3;  // the heading into the blocked sector
  ObstacleMemoryOptions edge_keep;
  edge_keep.blind_points_edge_keep_s = 15.0;
  ObstacleMemoryOptions five_s = edge_keep;  // every soft point kept blind_points_keep_s (before session 39)
  five_s.blind_points_edge_keep_s = 0.0;
  // The free travel at the set-off with the given memory and first view.
  auto free_at_setoff = [&](const ObstacleMemoryOptions& options, const std::vector<SonarColumn>& first_view) {
    return LookAround(options, first_view).FreeTravel(Pose2{}, right, 0.35, 5.0, /*use_blocked=*/false);
  };
  auto unblocked = [&](const std::vector<SonarColumn>& view) {
    return free_at_setoff(ObstacleMemoryOptions{}, Unblocked(view));
  };
  const double nothing = unblocked(corner);
  EXPECT_GT(nothing, 2.0);  // only the walls of the first turned view, about 2.8 m along the heading
  EXPECT_LT(free_at_setoff(edge_keep, corner), 0.3);
  EXPECT_EQ(free_at_setoff(five_s, corner), nothing);  // forgotten
  EXPECT_EQ(free_at_setoff(ObstacleMemoryOptions{}, corner), free_at_setoff(edge_keep, corner));  // the default since session 39
  EXPECT_EQ(free_at_setoff(edge_keep, wall), unblocked(wall));
  EXPECT_EQ(free_at_setoff(edge_keep, filling), unblocked(filling));
  ObstacleMemoryOptions bad;
  bad.blind_points_edge_keep_s = -1.0;
  EXPECT_NE(bad.Validate().find("blind_points_edge_keep_s"), std::string::npos);
  bad.blind_points_edge_keep_s = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(bad.Validate().find("blind_points_edge_keep_s"), std::string::npos);
}

// With blind_points_edge_keep_driving_only the corner's soft points, past the 5 s every soft point
// keeps, still close the heading for driving (FreeTravel with kept_edges, the default) but not for
// the queries that judge walls and openings: FreeTravel without kept_edges, PointsFreeTravel, the
// gathered points and the side distances see the memory as if the corner had not been seen (kept
// for every query, the points moved the centring and the openings' judgements, and the route with
// them). Within the 5 s, a fresh edge's points count for everything.
TEST(ObstacleMemory, KeptEdgePointsServeDrivingOnly) {
  const std::vector<SonarColumn> corner = BlockedOnTheRight(3.0);
  const double right = -0.3;
  ObstacleMemoryOptions kept;
  kept.blind_points_edge_keep_s = 15.0;
  kept.blind_points_edge_keep_driving_only = false;
  ObstacleMemoryOptions driving_only = kept;
  driving_only.blind_points_edge_keep_driving_only = true;
  const ObstacleMemory all = LookAround(kept, corner);
  const ObstacleMemory driving = LookAround(driving_only, corner);
  const ObstacleMemory none = LookAround(ObstacleMemoryOptions{}, Unblocked(corner));
  // Driving: the corner closes the heading as when kept for every query.
  const double closed = all.FreeTravel(Pose2{}, right, 0.35, 5.0, /*use_blocked=*/false);
  EXPECT_LT(closed, 0.3);
  EXPECT_EQ(driving.FreeTravel(Pose2{}, right, 0.35, 5.0, false), closed);
  // Judging: as if it had not been seen.
  const double nothing = none.FreeTravel(Pose2{}, right, 0.35, 5.0, false);
  EXPECT_GT(nothing, 2.0);
  EXPECT_EQ(driving.FreeTravel(Pose2{}, right, 0.35, 5.0, false, true, 0.0, 0.0, /*kept_edges=*/false), nothing);
  EXPECT_EQ(driving.PointsFreeTravel(Pose2{}, right, 0.35, 5.0), none.PointsFreeTravel(Pose2{}, right, 0.35, 5.0));
  EXPECT_LT(all.PointsFreeTravel(Pose2{}, right, 0.35, 5.0), 0.3);
  EXPECT_EQ(driving.Gathered().size(), none.Gathered().size());
  EXPECT_GT(all.Gathered().size(), none.Gathered().size());
  // Abeam within 1.5 m along the axis: the corner's points 0.6-1.2 m out along the blocked rays.
  double left_m = 0.0, right_m = 0.0, left_none = 0.0, right_none = 0.0, left_all = 0.0, right_all = 0.0;
  driving.SideDistances(Pose2{}, 0.0, 1.5, 1.8, &left_m, &right_m);
  none.SideDistances(Pose2{}, 0.0, 1.5, 1.8, &left_none, &right_none);
  all.SideDistances(Pose2{}, 0.0, 1.5, 1.8, &left_all, &right_all);
  EXPECT_EQ(left_m, left_none);
  EXPECT_EQ(right_m, right_none);
  EXPECT_GT(right_all, 0.0);
  EXPECT_TRUE(right_none < 0.0 || right_all < right_none);
  // A fresh edge (within blind_points_keep_s) counts for the judgements too.
  ObstacleMemory fresh(driving_only);
  fresh.Update(corner, Pose2{}, 0.0, 1.2);
  fresh.Gather(Pose2{}, 4.0);
  EXPECT_LT(fresh.PointsFreeTravel(Pose2{}, right, 0.35, 5.0), 0.3);
  EXPECT_LT(fresh.FreeTravel(Pose2{}, right, 0.35, 5.0, false, true, 0.0, 0.0, /*kept_edges=*/false), 0.3);
}

// Soft points are not put where the floor was seen from farther back, and floor seen later along
// the blocked rays removes them.
TEST(ObstacleMemory, SoftPointsYieldToFloorSeen) {
  const CameraModel cam = SonarCamera();
  std::vector<SonarColumn> blocked = WallScan(cam, 2.0);
  for (SonarColumn& c : blocked) {
    c.kind = SonarReturn::kBlockedNear;
    c.range_m = 0.0;
  }
  ObstacleMemoryOptions opt;
  opt.blocked_hold_s = 0.0;  // the soft points alone, not the blocked-near columns held over the next scan
  ObstacleMemory mem(opt);
  mem.Update(blocked, Pose2{}, 0.0, 1.2);
  mem.Gather(Pose2{}, 0.0);
  EXPECT_EQ(mem.FreeTravel(Pose2{}, 0.0, 0.35, 5.0, /*use_blocked=*/false), 0.0);  // soft points from 0.6 m
  // The same view a moment later shows floor from the bottom row up to a boundary at 1.4 m (short
  // of the 1.6 m that clears the blind zone of boundaries): the column is not blocked near, the
  // soft points along it go.
  ObstacleMemory again(opt);
  again.Update(blocked, Pose2{}, 0.0, 1.2);
  again.Update(WallScan(cam, 1.4), Pose2{}, 0.1, 1.2);
  again.Gather(Pose2{}, 0.1);
  EXPECT_NEAR(again.FreeTravel(Pose2{}, 0.0, 0.35, 5.0, /*use_blocked=*/false), 1.4 - 0.35, 0.05);
  // Backed away 1.5 m (odometry), the same floor is now seen free up to 2.9 m from there.
  const Pose2 back{-1.5, 0.0, 0.0};
  mem.Update(WallScan(cam, 2.9), back, 1.0, 1.2);
  mem.Gather(back, 1.0);
  EXPECT_NEAR(mem.FreeTravel(back, 0.0, 0.35, 5.0), 2.9 - 0.35, 0.05);
}

// The floor beside the robot's path (where the camera never looks) is known free where a column's
// floor showed from the bottom row across it in the near blind zone, or where the robot's disc
// was; a blocked-near column proves nothing there, and a cell marked one grid period (6.4 m) away
// does not count. Moved 0.2 m ahead, a disc of 0.22 m newly covers four cells at least 0.12 m
// beside its path: centres at bearings ±23° and ±31°, 0.38 and 0.29 m away, inside the 0.6 m blind
// range.
TEST(ObstacleMemory, UnknownBesideThePathUntilKnownFree) {
  const CameraModel cam = SonarCamera();
  const Pose2 at{};
  constexpr double kRadius = 0.22, kStep = 0.2, kInner = 0.12, kBlind = 0.6;
  ObstacleMemoryOptions opt;
  opt.mark_known_free = true;
  auto unknown = [&](const ObstacleMemory& m, double now_s) {
    return m.UnknownBeside(at, at.yaw, kRadius, kStep, kInner, now_s);
  };
  const ObstacleMemory fresh(opt);
  EXPECT_TRUE(unknown(fresh, 0.0));
  // Floor from the bottom row up to a wall 2.5 m ahead in every column: the cells are crossed.
  ObstacleMemory seen(opt);
  seen.Update(WallScan(cam, 2.5), at, 0.0, kBlind);
  EXPECT_FALSE(unknown(seen, 0.0));
  EXPECT_TRUE(unknown(seen, ObstacleMemoryOptions{}.keep_seconds + 1.0));  // forgotten
  // The same with columns whose bottom rows look like the floor (no step seen: unknown).
  std::vector<SonarColumn> floorlike = WallScan(cam, 2.5);
  for (SonarColumn& c : floorlike) c.kind = SonarReturn::kUnknown;
  ObstacleMemory like(opt);
  like.Update(floorlike, at, 0.0, kBlind);
  EXPECT_FALSE(unknown(like, 0.0));
  // Only the columns within 0.1 rad of the heading: they cross none of the four cells.
  std::vector<SonarColumn> narrow;
  for (const SonarColumn& c : WallScan(cam, 2.5))
    if (std::abs(c.bearing_rad) < 0.1) narrow.push_back(c);
  ASSERT_FALSE(narrow.empty());
  ObstacleMemory part(opt);
  part.Update(narrow, at, 0.0, kBlind);
  EXPECT_TRUE(unknown(part, 0.0));
  // Every column blocked near: something may stand anywhere in the blind zone.
  std::vector<SonarColumn> blocked = WallScan(cam, 2.5);
  for (SonarColumn& c : blocked) {
    c.kind = SonarReturn::kBlockedNear;
    c.range_m = 0.0;
  }
  ObstacleMemory near(opt);
  near.Update(blocked, at, 0.0, kBlind);
  EXPECT_TRUE(unknown(near, 0.0));
  // The disc stood 0.2 m ahead: it covered the four cells.
  ObstacleMemory trod(opt);
  trod.MarkFootprint(Pose2{kStep, 0.0, 0.0}, kRadius, 0.0);
  EXPECT_FALSE(unknown(trod, 0.0));
  // ...not when it stood there one grid period (64 cells of 0.1 m) on: the same cells of the torus.
  ObstacleMemory aliased(opt);
  aliased.MarkFootprint(Pose2{kStep + 6.4, 0.0, 0.0}, kRadius, 0.0);
  EXPECT_TRUE(unknown(aliased, 0.0));
  // Without mark_known_free nothing is marked.
  ObstacleMemory unmarked;
  unmarked.Update(WallScan(cam, 2.5), at, 0.0, kBlind);
  unmarked.MarkFootprint(Pose2{kStep, 0.0, 0.0}, kRadius, 0.0);
  EXPECT_TRUE(unknown(unmarked, 0.0));
  // Not moving, the disc covers nothing new.
  EXPECT_FALSE(fresh.UnknownBeside(at, at.yaw, kRadius, 0.0, kInner, 0.0));
}

}  // namespace
}  // namespace squint::explore
