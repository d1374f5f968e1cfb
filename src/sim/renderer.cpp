// The ray-cast renderer. Every ray leaves the camera's optical centre, so the horizontal
// visibility of the walls depends on the ray's bearing only: per frame a table over bearings
// (a few entries per image column) records the nearest wall at each bearing, and each sample
// then intersects that wall (and its neighbour's) analytically, so the geometry stays exact.
// Obstacles are listed per bearing bin; floor and ceiling are planes. Lighting is precomputed
// into light maps (floor grid, per-wall tables) from the ceiling lights with 2-D visibility.
// With n >= 3 samples per pixel side, sampling is adaptive (RenderOptions::adaptive): the pixel
// corners are traced first and a per-frame mask marks the pixels that wall edges, light panels,
// decals and flat items may cross (their outlines projected into the image; a vertical wall
// edge row by row); a pixel whose
// corners see one region of one plane is shaded once (box-filtered texture and light map over
// its footprint, summed-area tables), other pixels shade their samples on the planes met without a full trace (a pixel
// that one wall/floor or wall/ceiling line splits: each sample's side from that line's affine
// image equation, with no plane search).
// Mirrors reflect the robot's own body (RobotSpec: a matte vertical cylinder around the camera),
// which only reflected rays meet: a robot facing a mirror at distance d sees itself at 2d.
#include "squint/sim/renderer.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#if defined(__GNUC__) && defined(__x86_64__)
// (GCC 12 warns of the intrinsics' own undefined-register idiom, inside the header: PR 105593)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#pragma GCC diagnostic pop
#define SQUINT_RENDER_SIMD 1  // AVX-512 and AVX2 paths, chosen at run time (Renderer::Impl::simd, avx512)
#endif

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "textures.hpp"

namespace squint::sim {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kCell = 0.2;          // floor light-map resolution, metres (coarse: the map stays in cache)
constexpr double kWallCell = 0.1;      // wall light-map resolution, metres (interpolated along the wall)
constexpr double kLightRadius = 10.0;  // lights further away than this are ignored
constexpr double kCeilingBounce = 0.25;
constexpr double kLightPanelRadiance = 3.0;  // saturates at default exposure: lights are the brightest
constexpr double kOffPanelRadiance = 0.10;
constexpr int kMaxBinObstacles = 12;
constexpr int kMaxSamples = 16 * 16;  // samples per pixel (RenderOptions::supersample <= 16)
constexpr int kGammaLutSize = 4096;
// Adaptive supersampling: per-pixel marks of what may lie inside a pixel between its corners.
constexpr std::uint8_t kMaskGeometry = 1;  // a wall's vertical edge: trace every sample
constexpr std::uint8_t kMaskPattern = 2;   // a light panel, decal or flat item edge: sample the plane
constexpr double kMaxShadeRatio = 1.25;    // lighting over a pixel's corners that one shading may cover (decals)
constexpr double kGammaLutMax = 4.0;

std::uint64_t SplitMix(std::uint64_t x) {
  x += 0x9E3779B97F4A7C15ull;
  x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ull;
  x = (x ^ (x >> 27)) * 0x94D049BB133111EBull;
  return x ^ (x >> 31);
}

// One ray, 20 bytes so that a frame's rays stream through the cache.
struct Sample {
  float ca = 1, sa = 0;        // horizontal unit direction, robot frame
  float k = 0;                 // dz per horizontal metre
  float rk = 0;                // k < 0: horizontal distance to the floor (height / -k); k > 0: 1 / k
  int bin = 0;
  double RFloor() const { return k < 0 ? static_cast<double>(rk) : kInf; }
  double RangePerH() const { return std::sqrt(1.0 + static_cast<double>(k) * k); }  // 3-D per horizontal metre
};

enum class Surf : std::uint8_t { kNone, kFloor, kCeiling, kWall, kObsSide, kObsTop, kObsBottom, kInside, kBody };

struct Hit {
  Surf surf = Surf::kNone;
  int id = -1;
  double r = kInf;  // horizontal distance from the ray's origin
  double face_u = 0, face_v = 0;
  int face = 0;     // obstacle face index (for shading variety)
};

// What a hit looks like, without the texture lookup: radiance = texture(mat, tu, tv) * a + b
// (mat < 0: b alone). key1 names the plane (surface kind and id), key2 the region on it
// (material and decal / flat item / light panel); `exact` marks what adaptive sampling must
// not shade from its corners (obstacles, mirrors, stepped ceilings, nothing).
struct SurfPt {
  std::uint32_t key1 = 0, key2 = 0;
  int mat = -1;
  bool exact = false;  // (beside mat: 48 bytes, not 56)
  double tu = 0, tv = 0, a = 0, b = 0;
};
static_assert(sizeof(SurfPt) == 48);

}  // namespace

std::string RenderOptions::Validate() const {
  std::ostringstream why;
  if (supersample < 1 || supersample > 16) why << "supersample must lie in [1, 16]; ";
  if (!(exposure > 0) || !std::isfinite(exposure)) why << "exposure must be positive; ";
  if (!(gamma > 0) || !std::isfinite(gamma)) why << "gamma must be positive; ";
  if (!(noise_sigma >= 0) || !std::isfinite(noise_sigma)) why << "noise_sigma must not be negative; ";
  if (angle_bins_per_column < 1 || angle_bins_per_column > 64) why << "angle_bins_per_column must lie in [1, 64]; ";
  std::string s = why.str();
  if (s.size() >= 2) s.resize(s.size() - 2);
  return s;
}

struct Renderer::Impl {
  World world;
  CameraModel camera;
  RenderOptions options;
  int n = 1;  // supersampling factor
  std::vector<Sample> samples;  // pixel-major: pixel (u, v) owns n*n consecutive samples
  std::vector<Sample> centres;  // the pixels' central rays (label and range)
  // Bearing table.
  int bins = 0;
  double a_min = 0, d_a = 1;
  std::vector<double> edge_c, edge_s;  // robot-frame direction of each bin edge
  std::vector<double> edge_dx, edge_dy;  // per frame: its world-frame direction
  std::vector<int> edge_wall;
  std::vector<double> edge_t;
  std::vector<int> bin_count;
  std::vector<int> bin_obs;
  std::vector<double> obs_ox, obs_oy, obs_c, obs_s;  // per-frame ray origin in each obstacle's frame
  // Materials.
  std::vector<detail::TextureTable> tex;
  struct MatFast {
    double albedo, emission, mirror;
  };
  std::vector<MatFast> mats;
  // Floor grid.
  double gx0 = 0, gy0 = 0;
  int gnx = 0, gny = 0;
  struct Cell {  // one cache-friendly record per light-map cell
    float irr = 0;                     // floor irradiance
    std::int16_t floor_mat = 0, ceil_mat = 0;
    std::int16_t flat = -1;            // flat item over the cell, -2 several
    std::int32_t light = -1;           // light panel over the cell
  };
  std::vector<Cell> cells;
  std::vector<double> floor_sat;  // summed-area table of the cells' irradiance, (gnx + 1) × (gny + 1)
  // Walls.
  struct WallLight {
    std::size_t offset = 0;
    int nu = 0, nz = 0;
    double lo = 0;  // the wall's start (its along-coordinate at column 0)
    double fu_max = 0;          // nu - 2: the last column pair's start
    const float* irr = nullptr;  // &wall_irr[offset], set once wall_irr is complete
    std::size_t sat_offset = 0;  // into wall_sat: (nu + 1) × (nz + 1), cell (iu, iz) centred on sample (iu, iz)
  };
  std::vector<double> wall_sat;
  // What WallDistance needs of each wall, compact: its extent widened by 1e-7, and per frame the
  // camera's offset from its plane (coord - py or coord - px).
  struct WallFast {
    double lo = kInf, hi = -kInf, coord = 0, off = 0;
    double base = 0;  // per frame: the camera's coordinate along the wall (px or py)
    double sx = 0, sy = 0;  // the ray component across the wall: sx * dx + sy * dy (dy for walls along x)
    bool along_x = true;
    int material = 0;
    bool decals = false;  // any decal on it
  };
  std::vector<WallFast> wall_fast;  // [0] a sentinel that no ray meets (wall index -1), then the walls
  const WallFast* wf = nullptr;      // &wall_fast[1]
  std::vector<WallLight> wall_light;
  std::vector<float> wall_irr;  // per wall (offset): nz rows of nu samples along it
  std::vector<int> decal_begin, decal_end;  // per wall, into `decals`
  std::vector<Decal> decals;
  bool has_mirrors = false;
  // Obstacles.
  std::vector<float> obs_top_irr, obs_side_irr;
  bool uniform_ceiling = true;
  double ceiling_h = 2.8;
  // Output.
  std::vector<std::uint8_t> gamma_lut;
  std::vector<float> normal_table;
  // normal_table's noise as whole grey levels: a pixel's grey level g (an integer) plus the noise,
  // rounded half up, is g + noise_steps[i] exactly wherever noise_sigma * normal_table[i] + 0.5
  // lies clear of an integer (kNoiseExact elsewhere: the sum is taken in full). A 64 KB table
  // instead of 256 KB: the response pass's reads, one per pixel at random, stay in the caches.
  static constexpr std::int8_t kNoiseExact = -128;
  std::vector<std::int8_t> noise_steps;
  // Adaptive supersampling (n >= 3, undistorted camera).
  bool adaptive = false;
  // Vector paths for the 16-sample pixels (n * n a multiple of 8, SQUINT_RENDER_NO_SIMD unset):
  // AVX-512 (eight samples per step) where the CPU has AVX-512 F, VL and DQ, else AVX2 (four
  // samples per step; SQUINT_RENDER_NO_AVX512 forces it on an AVX-512 CPU). The same operations
  // in the same order on each lane, no fused multiply-adds, so the images are those of the
  // scalar code bit for bit.
  bool simd = false;
  bool avx512 = false;  // (simd) AVX-512, else AVX2
  std::vector<float> sample_soa;    // per pixel: its n*n samples' ca, then sa, k, rk (the same floats)
  std::vector<std::int32_t> sample_bin;  // per pixel: its samples' bins
  std::vector<float> corner_ca, corner_sa;  // (simd) the corner rays' ca and sa, and their bins
  std::vector<std::int32_t> corner_bin;
  std::vector<double> split_fx, split_fy;
  struct TexelsFast {  // per material, for PixelOnPlane's gathers (texels padded by 4 bytes)
    const std::uint8_t* texels;
    float inv_texel_m, gain;
  };
  std::vector<TexelsFast> texels_fast;
  struct PanelFast {  // per light, for ShadeOnPlaneSimd: its panel and the panel's radiance (as Shade)
    double cx, cy, hx, hy, radiance;
  };
  std::vector<PanelFast> panels;  // per sample of a pixel: (i + 0.5) / n, (j + 0.5) / n (PixelSplit)
  std::vector<Sample> corners;       // (width + 1) × (height + 1) rays through the pixel corners
  std::vector<Eigen::Vector3d> corner_dir;  // their robot-frame directions, unnormalised (affine in the image)
  std::vector<int> col_bin_lo, col_bin_hi;  // per pixel column: bearing bins its rays may use
  Eigen::Matrix3d cam_R_robot = Eigen::Matrix3d::Identity();
  std::vector<SurfPt> corner_pt;     // per frame
  // Per frame, per corner, compact (the once-shaded pixels' test reads only these): the plane and
  // region keys (key1 << 32 | key2, bit 63 set for `exact`) and the texture coordinates.
  std::vector<std::uint64_t> corner_cls;
  std::vector<double> corner_tu, corner_tv;
  std::vector<double> pix_mean;      // per frame, per pixel: mean radiance
  std::vector<double> corner_dx, corner_dy;  // per frame: world-frame horizontal directions
  std::vector<int> corner_id;                // per frame: bearing-table wall (PrepareAdaptive)
  std::vector<double> corner_r;
  std::vector<std::uint8_t> mask;    // per pixel: kMaskGeometry | kMaskPattern
  std::vector<double> col_max_t;     // per pixel column: farthest wall over its bins
  std::vector<double> col_near;      // per pixel column: nearest obstacle over its bins
  static constexpr int kMaxColObstacles = 8;
  std::vector<int> col_obs;          // per pixel column: the obstacles listed in its bins
  std::vector<int> col_nobs;         // how many (-1: more than kMaxColObstacles)
  std::vector<double> obs_near, obs_far;  // per frame: horizontal distance range of each obstacle
  std::vector<double> bin_near;      // per bin: nearest obstacle bounding circle
  // Per frame.
  double px = 0, py = 0, cyaw = 1, syaw = 0, cam_h = 0, frame_ceiling = 2.8;
  // The robot's body (mirror worlds): radius, top, albedo; per frame its side irradiance for
  // kBodyDirs outward normals (world-frame azimuth 2 pi i / kBodyDirs) and its top's.
  static constexpr int kBodyDirs = 8;
  double body_r = 0.25, body_top = 0.7, body_albedo = 0.35;
  double body_side_irr[kBodyDirs + 1] = {}, body_top_irr = 0;
  // The view's horizontal wedge (robot frame), widened by a margin, for culling what cannot be
  // seen: its right and left boundary directions, per margin (0: walls, 1: image outlines).
  struct Wedge {
    bool valid = false;  // narrower than a half turn
    double rc = 1, rs = 0, lc = 1, ls = 0;
  };
  Wedge wedge[2];

  // --- construction -------------------------------------------------------------------------
  void Init(const World& w, const CameraModel& cam, const RenderOptions& opt) {
    world = w;
    camera = cam;
    options = opt;
    n = opt.supersample;
    const std::string why = opt.Validate();
    if (!why.empty()) throw Error("render options: " + why);
    const std::string cam_why = cam.Validate();
    if (!cam_why.empty()) throw Error("renderer camera: " + cam_why);
    if (cam.height_m <= 0) throw Error("renderer camera: height_m must be positive");

    // Rays.
    auto make = [&](double u, double v) {
      const Eigen::Vector3d d = cam.PixelRayRobot({u, v});
      Sample s;
      double h = std::hypot(d.x(), d.y());
      if (h < 1e-9) h = 1e-9;
      s.ca = static_cast<float>(d.x() / h);
      s.sa = static_cast<float>(d.y() / h);
      s.k = static_cast<float>(d.z() / h);
      s.rk = s.k < 0 ? static_cast<float>(cam.height_m / -static_cast<double>(s.k))
                     : (s.k > 0 ? static_cast<float>(1.0 / static_cast<double>(s.k)) : 0.0f);
      return s;
    };
    samples.clear();
    for (int v = 0; v < cam.height; ++v)
      for (int u = 0; u < cam.width; ++u)
        for (int j = 0; j < n; ++j)
          for (int i = 0; i < n; ++i) samples.push_back(make(u + (i + 0.5) / n - 0.5, v + (j + 0.5) / n - 0.5));
    centres.clear();
    if (n > 1)
      for (int v = 0; v < cam.height; ++v)
        for (int u = 0; u < cam.width; ++u) centres.push_back(make(u, v));
    // At n = 2 the corner pass costs about what it saves (measured): full sampling there.
    adaptive = n >= 3 && opt.adaptive && !cam.HasDistortion();
    corners.clear();
    if (adaptive)
      for (int v = 0; v <= cam.height; ++v)
        for (int u = 0; u <= cam.width; ++u) corners.push_back(make(u - 0.5, v - 0.5));
    corner_dir.clear();
    if (adaptive) {
      const Eigen::Matrix3d robot_R_cam = cam.RobotRotationCamera();
      for (int v = 0; v <= cam.height; ++v)
        for (int u = 0; u <= cam.width; ++u)
          corner_dir.push_back(robot_R_cam * Eigen::Vector3d((u - 0.5 - cam.cx) / cam.fx, (v - 0.5 - cam.cy) / cam.fy, 1.0));
    }
    double lo = kInf, hi = -kInf;
    for (const auto* set : {&samples, &centres, &corners})
      for (const Sample& s : *set) {
        const double a = std::atan2(s.sa, s.ca);
        lo = std::min(lo, a), hi = std::max(hi, a);
      }
    bins = std::max(4, cam.width * n * opt.angle_bins_per_column);
    const double pad = 1e-6;
    a_min = lo - pad;
    d_a = (hi - lo + 2 * pad) / bins;
    auto bin_of = [&](Sample& s) {
      s.bin = std::clamp(static_cast<int>((std::atan2(s.sa, s.ca) - a_min) / d_a), 0, bins - 1);
    };
    for (Sample& s : samples) bin_of(s);
    for (Sample& s : centres) bin_of(s);
    for (Sample& s : corners) bin_of(s);
    simd = avx512 = false;
#ifdef SQUINT_RENDER_SIMD
    {
      const char* off = std::getenv("SQUINT_RENDER_NO_SIMD");
      const char* no512 = std::getenv("SQUINT_RENDER_NO_AVX512");
      avx512 = !(no512 && *no512) && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
               __builtin_cpu_supports("avx512dq");
      simd = adaptive && (n * n) % 8 == 0 && !(off && *off) && (avx512 || __builtin_cpu_supports("avx2"));
      avx512 = simd && avx512;
    }
#endif
    sample_soa.clear();
    sample_bin.clear();
    if (simd) {
      const std::size_t nn = static_cast<std::size_t>(n) * n, np = samples.size() / nn;
      sample_soa.resize(samples.size() * 4);
      sample_bin.resize(samples.size());
      for (std::size_t p = 0; p < np; ++p)
        for (std::size_t i = 0; i < nn; ++i) {
          const Sample& sm = samples[p * nn + i];
          float* b = &sample_soa[p * nn * 4];
          b[i] = sm.ca, b[nn + i] = sm.sa, b[2 * nn + i] = sm.k, b[3 * nn + i] = sm.rk;
          sample_bin[p * nn + i] = sm.bin;
        }
      corner_ca.clear(), corner_sa.clear(), corner_bin.clear();
      for (const Sample& c : corners) corner_ca.push_back(c.ca), corner_sa.push_back(c.sa), corner_bin.push_back(c.bin);
      split_fx.resize(nn);
      split_fy.resize(nn);
      const double inv_n = 1.0 / n;  // as PixelSplit steps
      for (int j = 0, k = 0; j < n; ++j)
        for (int i = 0; i < n; ++i, ++k) split_fx[k] = (i + 0.5) * inv_n, split_fy[k] = (j + 0.5) * inv_n;
    }
    if (adaptive) {
      const int cw = cam.width + 1;
      col_bin_lo.assign(cam.width, bins);
      col_bin_hi.assign(cam.width, 0);
      for (int v = 0; v <= cam.height; ++v)
        for (int u = 0; u < cam.width; ++u)
          for (int du = 0; du < 2; ++du) {
            const int b = corners[static_cast<std::size_t>(v) * cw + u + du].bin;
            col_bin_lo[u] = std::min(col_bin_lo[u], std::max(0, b - 1));
            col_bin_hi[u] = std::max(col_bin_hi[u], std::min(bins - 1, b + 1));
          }
      cam_R_robot = cam.RobotRotationCamera().transpose();
      corner_pt.resize(corners.size());
      corner_cls.resize(corners.size());
      corner_tu.resize(corners.size());
      corner_tv.resize(corners.size());
      corner_dx.resize(corners.size());
      pix_mean.resize(static_cast<std::size_t>(cam.width) * cam.height);
      corner_dy.resize(corners.size());
      corner_id.resize(corners.size());
      corner_r.resize(corners.size());
      mask.resize(static_cast<std::size_t>(cam.width) * cam.height);
      col_max_t.resize(cam.width);
      col_near.resize(cam.width);
      col_obs.resize(static_cast<std::size_t>(cam.width) * kMaxColObstacles);
      col_nobs.resize(cam.width);
    }
    edge_c.resize(bins + 1);
    edge_dx.resize(bins + 1);
    edge_dy.resize(bins + 1);
    edge_s.resize(bins + 1);
    for (int e = 0; e <= bins; ++e) {
      edge_c[e] = std::cos(a_min + e * d_a);
      edge_s[e] = std::sin(a_min + e * d_a);
    }
    // Margins: walls 1e-5 rad (the bearing table's tolerances are far smaller); image outlines
    // two pixels (MarkPolygon marks pixels half a pixel beyond a polygon).
    const double margins[2] = {1e-5, 2.0 / std::min(cam.fx, cam.fy)};
    for (int q = 0; q < 2; ++q) {
      const double lo_a = a_min - margins[q], hi_a = a_min + bins * d_a + margins[q];
      wedge[q].valid = hi_a - lo_a < kPi - 1e-3;
      wedge[q].rc = std::cos(lo_a), wedge[q].rs = std::sin(lo_a), wedge[q].lc = std::cos(hi_a), wedge[q].ls = std::sin(hi_a);
    }
    edge_wall.assign(bins + 1, -1);
    edge_t.assign(bins + 1, kInf);
    bin_count.assign(bins, 0);
    bin_obs.assign(static_cast<std::size_t>(bins) * kMaxBinObstacles, 0);
    bin_near.assign(bins, kInf);
    obs_ox.assign(world.obstacles.size(), 0);
    obs_oy = obs_c = obs_s = obs_near = obs_far = obs_ox;

    for (std::size_t i = 0; i < world.materials.size(); ++i)
      tex.push_back(detail::MakeTexture(world.materials[i], static_cast<std::uint32_t>(i + 1)));
    for (const Material& m : world.materials) mats.push_back({m.albedo, m.emission, m.mirror});

    uniform_ceiling = true;
    ceiling_h = world.corridors.front().height_m;
    for (const Corridor& c : world.corridors) uniform_ceiling = uniform_ceiling && c.height_m == ceiling_h;

    BuildLightMaps();
    panels.clear();
    for (const Light& lt : world.lights)
      panels.push_back({lt.centre.x(), lt.centre.y(), lt.half_x, lt.half_y,
                        lt.on ? kLightPanelRadiance * std::max(0.3, lt.intensity) : kOffPanelRadiance});
    texels_fast.clear();
    if (simd)
      for (detail::TextureTable& t : tex) {
        t.texels.resize(static_cast<std::size_t>(detail::kTexSize) * detail::kTexSize + 4, 0);  // (32-bit gathers of the last texels)
        texels_fast.push_back({t.texels.data(), t.inv_texel_m, t.gain});
      }

    // Decals grouped by wall.
    decals = world.decals;
    std::stable_sort(decals.begin(), decals.end(), [](const Decal& a, const Decal& b) { return a.wall < b.wall; });
    decal_begin.assign(world.walls.size(), 0);
    decal_end.assign(world.walls.size(), 0);
    for (std::size_t i = 0; i < decals.size(); ++i) {
      if (decal_end[decals[i].wall] == 0) decal_begin[decals[i].wall] = static_cast<int>(i);
      decal_end[decals[i].wall] = static_cast<int>(i) + 1;
    }
    for (const WallSegment& ws : world.walls) has_mirrors = has_mirrors || world.materials[ws.material].mirror > 0;
    wall_fast.assign(1, WallFast{});
    for (const WallSegment& ws : world.walls)
      wall_fast.push_back({ws.lo - 1e-7, ws.hi + 1e-7, ws.coord, 0.0, 0.0, ws.along_x ? 0.0 : 1.0, ws.along_x ? 1.0 : 0.0, ws.along_x, ws.material, false});
    for (std::size_t k = 0; k < world.walls.size(); ++k) wall_fast[k + 1].decals = decal_end[k] > decal_begin[k];
    wf = wall_fast.data() + 1;
    for (const Decal& d : decals) has_mirrors = has_mirrors || world.materials[d.material].mirror > 0;
    body_r = world.robot.radius_m;
    body_top = cam.height_m + world.robot.body_above_camera_m;
    body_albedo = world.robot.body_grey;

    gamma_lut.resize(kGammaLutSize);
    for (int i = 0; i < kGammaLutSize; ++i) {
      const double l = (i + 0.5) * kGammaLutMax / kGammaLutSize;
      gamma_lut[i] = static_cast<std::uint8_t>(std::lround(255.0 * std::pow(std::min(1.0, l), 1.0 / opt.gamma)));
    }
    std::mt19937_64 rng(12345);
    std::normal_distribution<float> g(0.0f, 1.0f);
    normal_table.resize(65536);
    for (float& x : normal_table) x = g(rng);
    noise_steps.resize(normal_table.size());
    for (std::size_t i = 0; i < normal_table.size(); ++i) {
      // g + x + 0.5 is rounded twice in Respond, each time by far less than 1e-9 (|g| <= 255 and
      // |x| < 128): its floor is g + floor(x + 0.5) when x + 0.5 lies further than that from an
      // integer.
      const double x = opt.noise_sigma * normal_table[i];
      const double y = x + 0.5, q = std::floor(y);
      const bool clear = y - q > 1e-9 && q + 1 - y > 1e-9 && std::abs(q) <= 127;
      noise_steps[i] = clear ? static_cast<std::int8_t>(q) : kNoiseExact;
    }
    // (RespondRowSimd reads both tables by 32-bit gathers: three bytes of padding)
    gamma_lut.resize(kGammaLutSize + 3, 0);
    noise_steps.resize(normal_table.size() + 3, 0);
  }

  // The lights within reach of p and not hidden from it by a wall (2-D visibility: walls reach
  // the ceiling).
  std::vector<int> VisibleLights(const Eigen::Vector2d& p) const {
    std::vector<int> out;
    for (std::size_t i = 0; i < world.lights.size(); ++i) {
      const Light& l = world.lights[i];
      if (!l.on) continue;
      const Eigen::Vector2d d2 = p - l.centre;
      const double hd = d2.norm();
      if (hd > kLightRadius) continue;
      if (hd > 1e-6) {
        const auto hit = world.CastWalls(l.centre, d2 / hd);  // from the light towards the point
        if (hit && hit->first < hd - 2e-3) continue;
      }
      out.push_back(static_cast<int>(i));
    }
    return out;
  }

  // Irradiance at a point with a given unit normal from the given (visible) lights.
  double Irradiance(const Eigen::Vector3d& p, const Eigen::Vector3d& normal, const std::vector<int>& visible) const {
    double e = world.ambient;
    for (int i : visible) {
      const Light& l = world.lights[i];
      const Eigen::Vector3d v(l.centre.x() - p.x(), l.centre.y() - p.y(), l.z_m - p.z());
      const double dist2 = v.squaredNorm();
      if (dist2 < 1e-6) continue;
      const double dist = std::sqrt(dist2);
      const double cos_e = v.z() / dist;
      const double cos_r = v.dot(normal) / dist;
      if (cos_e <= 0 || cos_r <= 0) continue;
      e += l.intensity * l.z_m * l.z_m * cos_e * cos_r / dist2;
    }
    return e;
  }

  void BuildLightMaps() {
    const Box2 b = world.Bounds();
    gx0 = b.x0;
    gy0 = b.y0;
    gnx = std::max(1, static_cast<int>(std::ceil((b.x1 - b.x0) / kCell)));
    gny = std::max(1, static_cast<int>(std::ceil((b.y1 - b.y0) / kCell)));
    const std::size_t n_cells = static_cast<std::size_t>(gnx) * gny;
    cells.assign(n_cells, Cell{static_cast<float>(world.ambient), 0, 0, -1, -1});
    for (int j = 0; j < gny; ++j)
      for (int i = 0; i < gnx; ++i) {
        const Eigen::Vector2d c(gx0 + (i + 0.5) * kCell, gy0 + (j + 0.5) * kCell);
        const std::size_t idx = static_cast<std::size_t>(j) * gnx + i;
        // Materials: the first corridor containing the cell (or nearest by margin).
        int owner = -1;
        for (std::size_t k = 0; k < world.corridors.size() && owner < 0; ++k)
          if (world.corridors[k].rect.Contains(c, kCell)) owner = static_cast<int>(k);
        if (owner < 0) owner = 0;
        cells[idx].floor_mat = static_cast<std::int16_t>(world.corridors[owner].floor_material);
        cells[idx].ceil_mat = static_cast<std::int16_t>(world.corridors[owner].ceiling_material);
        if (!world.IsFree(c)) continue;
        cells[idx].irr = static_cast<float>(Irradiance({c.x(), c.y(), 0.0}, {0, 0, 1}, VisibleLights(c)));
      }
    // Light panels and flat items into the grid (cells they overlap).
    auto mark = [&](double x0, double y0, double x1, double y1, auto&& fn) {
      const int i0 = std::max(0, static_cast<int>(std::floor((x0 - gx0) / kCell)));
      const int i1 = std::min(gnx - 1, static_cast<int>(std::floor((x1 - gx0) / kCell)));
      const int j0 = std::max(0, static_cast<int>(std::floor((y0 - gy0) / kCell)));
      const int j1 = std::min(gny - 1, static_cast<int>(std::floor((y1 - gy0) / kCell)));
      for (int j = j0; j <= j1; ++j)
        for (int i = i0; i <= i1; ++i) fn(static_cast<std::size_t>(j) * gnx + i);
    };
    for (std::size_t k = 0; k < world.lights.size(); ++k) {
      const Light& l = world.lights[k];
      mark(l.centre.x() - l.half_x, l.centre.y() - l.half_y, l.centre.x() + l.half_x, l.centre.y() + l.half_y,
           [&](std::size_t idx) { cells[idx].light = static_cast<std::int32_t>(k); });
    }
    for (std::size_t k = 0; k < world.flat_items.size(); ++k) {
      const FlatItem& f = world.flat_items[k];
      const double r = std::hypot(f.half_x, f.half_y);
      mark(f.centre.x() - r, f.centre.y() - r, f.centre.x() + r, f.centre.y() + r, [&](std::size_t idx) {
        cells[idx].flat = cells[idx].flat == -1 ? static_cast<std::int16_t>(k) : std::int16_t{-2};
      });
    }
    // Walls.
    wall_light.clear();
    wall_irr.clear();
    for (const WallSegment& ws : world.walls) {
      WallLight wl;
      wl.offset = wall_irr.size();
      wl.nu = static_cast<int>(std::ceil((ws.hi - ws.lo) / kWallCell)) + 2;
      wl.nz = static_cast<int>(std::ceil(ws.height_m / kWallCell)) + 1;
      wl.lo = ws.lo;
      wall_light.push_back(wl);
      const Eigen::Vector3d normal(ws.normal.x(), ws.normal.y(), 0.0);
      for (int iu = 0; iu < wl.nu; ++iu) {
        const double along = std::min(ws.hi, ws.lo + iu * kWallCell);
        Eigen::Vector2d p = ws.along_x ? Eigen::Vector2d(along, ws.coord) : Eigen::Vector2d(ws.coord, along);
        p += ws.normal * 1e-3;
        const std::vector<int> visible = VisibleLights(p);
        for (int iz = 0; iz < wl.nz; ++iz) {
          const double z = std::min(ws.height_m - 1e-3, iz * kWallCell);
          wall_irr.push_back(static_cast<float>(Irradiance({p.x(), p.y(), z}, normal, visible)));
        }
      }
    }

    // Stored height-major (rows along the wall): the two columns a lookup interpolates, and
    // neighbouring samples at one height, share cache lines.
    {
      std::vector<float> rows(wall_irr.size());
      for (const WallLight& wl : wall_light)
        for (int iu = 0; iu < wl.nu; ++iu)
          for (int iz = 0; iz < wl.nz; ++iz) rows[wl.offset + static_cast<std::size_t>(iz) * wl.nu + iu] = wall_irr[wl.offset + static_cast<std::size_t>(iu) * wl.nz + iz];
      wall_irr.swap(rows);
    }
    for (WallLight& wl : wall_light) {
      wl.fu_max = wl.nu - 2.0;
      wl.irr = wall_irr.data() + wl.offset;
    }
    // Summed-area tables of the light maps, for mean irradiance over a pixel's footprint.
    floor_sat.assign(static_cast<std::size_t>(gnx + 1) * (gny + 1), 0.0);
    for (int j = 0; j < gny; ++j)
      for (int i = 0; i < gnx; ++i)
        floor_sat[static_cast<std::size_t>(j + 1) * (gnx + 1) + i + 1] = cells[static_cast<std::size_t>(j) * gnx + i].irr +
                                                                          floor_sat[static_cast<std::size_t>(j) * (gnx + 1) + i + 1] +
                                                                          floor_sat[static_cast<std::size_t>(j + 1) * (gnx + 1) + i] -
                                                                          floor_sat[static_cast<std::size_t>(j) * (gnx + 1) + i];
    wall_sat.clear();
    for (WallLight& wl : wall_light) {  // rows along the wall (iu), columns up it (iz)
      wl.sat_offset = wall_sat.size();
      const int sn = wl.nz + 1;
      wall_sat.resize(wall_sat.size() + static_cast<std::size_t>(wl.nu + 1) * sn, 0.0);
      double* t = wall_sat.data() + wl.sat_offset;
      for (int iu = 0; iu < wl.nu; ++iu)
        for (int iz = 0; iz < wl.nz; ++iz)
          t[(iu + 1) * sn + iz + 1] = wl.irr[iz * wl.nu + iu] + t[iu * sn + iz + 1] + t[(iu + 1) * sn + iz] - t[iu * sn + iz];
    }

    // Obstacles: top and mean side irradiance.
    obs_top_irr.clear();
    obs_side_irr.clear();
    for (const Obstacle& o : world.obstacles) {
      const Eigen::Vector3d top(o.centre.x(), o.centre.y(), o.z1);
      obs_top_irr.push_back(static_cast<float>(Irradiance(top, {0, 0, 1}, VisibleLights(o.centre))));
      const double r = o.shape == Obstacle::Shape::kCylinder ? o.radius : std::max(o.half_x, o.half_y);
      double side = 0;
      for (int q = 0; q < 4; ++q) {
        const Eigen::Vector3d nrm(std::cos(q * kPi / 2), std::sin(q * kPi / 2), 0);
        const Eigen::Vector3d p = Eigen::Vector3d(o.centre.x(), o.centre.y(), 0.5 * (o.z0 + o.z1)) + nrm * (r + 0.01);
        side += Irradiance(p, nrm, VisibleLights(p.head<2>()));
      }
      obs_side_irr.push_back(static_cast<float>(side / 4));
    }
  }

  // --- per frame --------------------------------------------------------------------------------
  void PrepareFrame(const Pose2& pose) {
    px = pose.x;
    py = pose.y;
    cyaw = std::cos(pose.yaw);
    syaw = std::sin(pose.yaw);
    cam_h = camera.height_m;
    frame_ceiling = uniform_ceiling ? ceiling_h : std::max(cam_h + 0.01, world.CeilingAt({px, py}));
    for (std::size_t w = 1; w < wall_fast.size(); ++w) {
      WallFast& f = wall_fast[w];
      f.off = f.coord - (f.along_x ? py : px);
      f.base = f.along_x ? px : py;
    }
    if (has_mirrors) PrepareBodyLight();
    const double yaw0 = pose.yaw + a_min;
    // Walls into the bearing table (the bin edges' world-frame directions first).
    for (int e = 0; e <= bins; ++e) {
      edge_dx[e] = cyaw * edge_c[e] - syaw * edge_s[e];
      edge_dy[e] = syaw * edge_c[e] + cyaw * edge_s[e];
    }
    std::fill(edge_wall.begin(), edge_wall.end(), -1);
    std::fill(edge_t.begin(), edge_t.end(), kInf);
    for (std::size_t w = 0; w < world.walls.size(); ++w) {
      const WallSegment& ws = world.walls[w];
      double ax, ay, bx, by;
      if (ws.along_x) ax = ws.lo, ay = ws.coord, bx = ws.hi, by = ws.coord;
      else ax = ws.coord, ay = ws.lo, bx = ws.coord, by = ws.hi;
      const double side = ws.along_x ? (py - ws.coord) * ws.normal.y() : (px - ws.coord) * ws.normal.x();
      if (side <= 1e-12) continue;  // seen from behind or edge-on
      {
        const double xs[2] = {ax, bx}, ys[2] = {ay, by};
        if (OutsideWedge(0, xs, ys, 2)) continue;  // meets none of the table's rays
      }
      double a0 = WrapPi(std::atan2(ay - py, ax - px) - yaw0);
      double a1 = WrapPi(std::atan2(by - py, bx - px) - yaw0);
      if (a0 > a1) std::swap(a0, a1);
      double lo, hi;
      if (a1 - a0 > kPi) lo = a1, hi = kPi + 1e-9 + (a0 + kPi);  // wraps behind: [a1, pi] u [-pi, a0]
      else lo = a0, hi = a1;
      int e0 = static_cast<int>(std::floor(lo / d_a)) - 1, e1 = static_cast<int>(std::ceil(hi / d_a)) + 1;
      e0 = std::max(e0, 0);
      e1 = std::min(e1, bins);
      const double* across = ws.along_x ? edge_dy.data() : edge_dx.data();  // the ray across the wall
      const double* other = ws.along_x ? edge_dx.data() : edge_dy.data();
      const double num = ws.coord - (ws.along_x ? py : px), base = ws.along_x ? px : py;
      const double lo_e = ws.lo - 1e-9, hi_e = ws.hi + 1e-9;
      int e = e0;
#ifdef SQUINT_RENDER_SIMD
      if (avx512) e = WallEdgesSimd(static_cast<int>(w), e0, e1, across, other, num, base, lo_e, hi_e);
      else if (simd) e = WallEdgesAvx2(static_cast<int>(w), e0, e1, across, other, num, base, lo_e, hi_e);
#endif
      for (; e <= e1; ++e) {
        if (std::abs(across[e]) < 1e-12) continue;
        const double t = num / across[e];
        const double along = base + t * other[e];
        if (t <= 0 || t >= edge_t[e] || along < lo_e || along > hi_e) continue;
        edge_t[e] = t;
        edge_wall[e] = static_cast<int>(w);
      }
    }
    // Obstacles into bins.
    std::fill(bin_count.begin(), bin_count.end(), 0);
    std::fill(bin_near.begin(), bin_near.end(), kInf);
    for (std::size_t o = 0; o < world.obstacles.size(); ++o) {
      const Obstacle& ob = world.obstacles[o];
      obs_c[o] = std::cos(ob.yaw);
      obs_s[o] = std::sin(ob.yaw);
      const double rx = px - ob.centre.x(), ry = py - ob.centre.y();
      obs_ox[o] = obs_c[o] * rx + obs_s[o] * ry;
      obs_oy[o] = -obs_s[o] * rx + obs_c[o] * ry;
      const double rad = ob.shape == Obstacle::Shape::kCylinder ? ob.radius : std::hypot(ob.half_x, ob.half_y);
      const double d = std::hypot(rx, ry);
      const double near = std::max(0.0, d - rad);
      obs_near[o] = near;
      obs_far[o] = d + rad;
      auto add = [&](int b0, int b1) {
        for (int b = std::max(b0, 0); b <= std::min(b1, bins - 1); ++b) {
          bin_near[b] = std::min(bin_near[b], near);
          int& cnt = bin_count[b];
          if (cnt < kMaxBinObstacles) bin_obs[static_cast<std::size_t>(b) * kMaxBinObstacles + cnt] = static_cast<int>(o);
          ++cnt;  // counts past the capacity mean "test all obstacles"
        }
      };
      if (d <= rad + 1e-9) {
        add(0, bins - 1);
        continue;
      }
      const double centre = WrapPi(std::atan2(-ry, -rx) - yaw0);
      const double half = std::asin(std::min(1.0, rad / d));
      // The bins span [0, bins * d_a]; the interval may meet it directly or shifted by a turn.
      for (double shift : {-2 * kPi, 0.0, 2 * kPi}) {
        const double lo = centre - half + shift, hi = centre + half + shift;
        if (hi < 0 || lo > bins * d_a) continue;
        add(static_cast<int>(std::floor(lo / d_a)) - 1, static_cast<int>(std::ceil(hi / d_a)) + 1);
      }
    }
  }

#ifdef SQUINT_RENDER_SIMD
  // The bearing table's loop over edges [e0, e1] for wall w, eight edges per AVX-512 step with the
  // scalar loop's tests (each negated, as its `continue` is taken): the edges it covers, from e0.
  [[gnu::target("avx512f,avx512vl,avx512dq")]] int WallEdgesSimd(int w, int e0, int e1, const double* across, const double* other,
                                                                double num, double base, double lo_e, double hi_e) {
    int e = e0;
    for (; e + 7 <= e1; e += 8) {
      const __m512d a = _mm512_loadu_pd(across + e), et = _mm512_loadu_pd(&edge_t[e]);
      const __m512d t = _mm512_div_pd(_mm512_set1_pd(num), a);
      const __m512d along = _mm512_add_pd(_mm512_set1_pd(base), _mm512_mul_pd(t, _mm512_loadu_pd(other + e)));
      const __mmask8 take = _mm512_cmp_pd_mask(_mm512_abs_pd(a), _mm512_set1_pd(1e-12), _CMP_NLT_UQ) &
                            _mm512_cmp_pd_mask(t, _mm512_setzero_pd(), _CMP_NLE_UQ) & _mm512_cmp_pd_mask(t, et, _CMP_NGE_UQ) &
                            _mm512_cmp_pd_mask(along, _mm512_set1_pd(lo_e), _CMP_NLT_UQ) &
                            _mm512_cmp_pd_mask(along, _mm512_set1_pd(hi_e), _CMP_NGT_UQ);
      _mm512_mask_storeu_pd(&edge_t[e], take, t);
      _mm256_mask_storeu_epi32(&edge_wall[e], take, _mm256_set1_epi32(w));
    }
    return e;
  }
#endif

  // The body's irradiance this frame: its side at mid-height for kBodyDirs outward normals and
  // its top, from the lights visible from the robot's centre (as obstacles are lit; the body
  // casts no shadow). Allocation-free: the lights are tested one by one.
  void PrepareBodyLight() {
    const double mid = 0.5 * body_top;
    for (int i = 0; i < kBodyDirs; ++i) body_side_irr[i] = world.ambient;
    body_top_irr = world.ambient;
    for (const Light& l : world.lights) {
      if (!l.on) continue;
      const Eigen::Vector2d d2(px - l.centre.x(), py - l.centre.y());
      const double hd = d2.norm();
      if (hd > kLightRadius) continue;
      if (hd > 1e-6) {
        const auto hit = world.CastWalls(l.centre, d2 / hd);
        if (hit && hit->first < hd - 2e-3) continue;
      }
      const double scale = l.intensity * l.z_m * l.z_m;
      for (int i = 0; i < kBodyDirs; ++i) {
        const double a = 2 * kPi * i / kBodyDirs, nx = std::cos(a), ny = std::sin(a);
        const double sx = px + nx * (body_r + 0.01), sy = py + ny * (body_r + 0.01);
        const double vx = l.centre.x() - sx, vy = l.centre.y() - sy, vz = l.z_m - mid;
        const double dist2 = vx * vx + vy * vy + vz * vz, dist = std::sqrt(dist2);
        const double cos_e = vz / dist, cos_r = (vx * nx + vy * ny) / dist;
        if (cos_e > 0 && cos_r > 0) body_side_irr[i] += scale * cos_e * cos_r / dist2;
      }
      const double vx = l.centre.x() - px, vy = l.centre.y() - py, vz = l.z_m - body_top;
      const double dist2 = vx * vx + vy * vy + vz * vz;
      if (vz > 0) body_top_irr += scale * (vz / std::sqrt(dist2)) * (vz / std::sqrt(dist2)) / dist2;
    }
    body_side_irr[kBodyDirs] = body_side_irr[0];
  }

  // The robot's body against a reflected ray from (ox, oy, oz) with horizontal direction
  // (dx, dy) and slope k; updates `hit` when nearer. A ray starting inside the body (a primary
  // ray: the camera is inside it) never meets it.
  void HitBody(double ox, double oy, double oz, double dx, double dy, double k, Hit& hit) const {
    const double lx = ox - px, ly = oy - py;
    const double cc = lx * lx + ly * ly - body_r * body_r;
    if (cc <= 0) return;
    const double b = lx * dx + ly * dy;
    const double disc = b * b - cc;
    if (b >= 0 || disc < 0) return;  // heading away, or passing by
    const double sq = std::sqrt(disc);
    const double tin = -b - sq, tout = -b + sq;
    if (tin >= hit.r) return;
    const double z_in = oz + k * tin;
    if (z_in >= 0 && z_in <= body_top) {
      hit = {Surf::kBody, -1, tin, std::atan2(ly + dy * tin, lx + dx * tin), z_in, 0};
    } else if (z_in > body_top && k < 0) {
      const double t = (body_top - oz) / k;
      if (t <= tout && t < hit.r) hit = {Surf::kBody, -1, t, 0, body_top, 1};
    }
  }

  // Whether every one of the world points (xs[i], ys[i]) lies outside wedge q on one and the same
  // side (so that their convex hull cannot be seen).
  bool OutsideWedge(int q, const double* xs, const double* ys, int count) const {
    const Wedge& w = wedge[q];
    if (!w.valid) return false;
    bool all_left = true, all_right = true;
    for (int i = 0; i < count; ++i) {
      const double wx = xs[i] - px, wy = ys[i] - py;
      const double rx = cyaw * wx + syaw * wy, ry = -syaw * wx + cyaw * wy;  // robot frame
      all_left = all_left && w.lc * ry - w.ls * rx > 0;   // counter-clockwise of the left boundary
      all_right = all_right && w.rc * ry - w.rs * rx < 0;  // clockwise of the right boundary
    }
    return all_left || all_right;
  }

  // Horizontal distance along (dx, dy) from the camera to wall w; infinity when the ray misses it.
  // Branch-free: a ray parallel to the wall gives 0/0 or an infinite t, which the tests reject,
  // and w = -1 (no wall) reads the sentinel, whose empty extent rejects every ray.
  [[gnu::always_inline]] double WallDistance(int w, double dx, double dy) const {
    const WallFast& f = wf[w];
    // (sx, sy) is (0, 1) or (1, 0): the products pick dx or dy exactly.
    const double t = f.off / (f.sx * dx + f.sy * dy);
    const double along = f.base + t * (f.sy * dx + f.sx * dy);
    return (t > 0 && along >= f.lo && along <= f.hi) ? t : kInf;
  }

  // Obstacle o against the ray from (ox, oy, oz) (world) with horizontal direction (dx, dy) and
  // slope k; updates `hit` when nearer. (lx, ly) is the ray origin in the obstacle's frame.
  void HitObstacle(int o, double lx, double ly, double oz, double dx, double dy, double k, Hit& hit) const {
    const Obstacle& ob = world.obstacles[o];
    double tin, tout;
    int face = 0;
    // The direction in the obstacle's frame, as the origin (lx, ly) is: for every shape, since a
    // cylinder's hit point (its texture coordinate) and the origin must be in the same frame.
    const double c = obs_c[o], s = obs_s[o];
    const double ldx = c * dx + s * dy, ldy = -s * dx + c * dy;
    if (ob.shape == Obstacle::Shape::kBox) {
      double t0x, t1x, t0y, t1y;
      if (std::abs(ldx) < 1e-12) {
        if (std::abs(lx) > ob.half_x) return;
        t0x = -kInf, t1x = kInf;
      } else {
        t0x = (-ob.half_x - lx) / ldx, t1x = (ob.half_x - lx) / ldx;
        if (t0x > t1x) std::swap(t0x, t1x);
      }
      if (std::abs(ldy) < 1e-12) {
        if (std::abs(ly) > ob.half_y) return;
        t0y = -kInf, t1y = kInf;
      } else {
        t0y = (-ob.half_y - ly) / ldy, t1y = (ob.half_y - ly) / ldy;
        if (t0y > t1y) std::swap(t0y, t1y);
      }
      tin = std::max(t0x, t0y);
      tout = std::min(t1x, t1y);
      if (tin > tout || tout <= 0) return;
      face = t0x > t0y ? (ldx > 0 ? 0 : 1) : (ldy > 0 ? 2 : 3);
    } else {
      const double b = lx * ldx + ly * ldy;
      const double cc = lx * lx + ly * ly - ob.radius * ob.radius;
      const double disc = b * b - cc;
      if (disc < 0) return;
      const double sq = std::sqrt(disc);
      tin = -b - sq;
      tout = -b + sq;
      if (tout <= 0) return;
    }
    if (tin >= hit.r) return;
    const double t_side = std::max(tin, 0.0);
    const double z_in = oz + k * t_side;
    if (z_in >= ob.z0 && z_in <= ob.z1) {
      if (tin <= 0) {  // the origin is inside the obstacle
        hit = {Surf::kInside, o, 0.0, 0, 0, 0};
        return;
      }
      hit.surf = Surf::kObsSide;
      hit.id = o;
      hit.r = tin;
      hit.face = face;
      const double hx = lx + ldx * tin, hy = ly + ldy * tin;
      if (ob.shape == Obstacle::Shape::kBox) hit.face_u = (face < 2 ? hy : hx);
      else hit.face_u = std::atan2(hy, hx) * ob.radius, hit.face = (hx > 0) + 2 * (hy > 0);
      hit.face_v = z_in;
      return;
    }
    if (z_in > ob.z1 && k < 0) {
      const double t = (ob.z1 - oz) / k;
      if (t <= tout && t < hit.r) {
        hit.surf = Surf::kObsTop;
        hit.id = o;
        hit.r = t;
        hit.face_u = lx + ldx * t;
        hit.face_v = ly + ldy * t;
      }
    } else if (z_in < ob.z0 && k > 0) {
      const double t = (ob.z0 - oz) / k;
      if (t <= tout && t < hit.r) {
        hit.surf = Surf::kObsBottom;
        hit.id = o;
        hit.r = t;
      }
    }
  }

  // The fast path: camera origin, bearing table.
  [[gnu::always_inline]] Hit Trace(const Sample& s, double& dx, double& dy) const {
    dx = cyaw * s.ca - syaw * s.sa;
    dy = syaw * s.ca + cyaw * s.sa;
    Hit hit;
    const int w0 = edge_wall[s.bin], w1 = edge_wall[s.bin + 1];
    const double t0 = WallDistance(w0, dx, dy);
    const double t1 = w1 != w0 ? WallDistance(w1, dx, dy) : kInf;
    if (t0 <= t1) {
      hit.r = t0, hit.id = w0;
    } else {
      hit.r = t1, hit.id = w1;
    }
    if (hit.r == kInf) {  // a sliver wall inside the bin: fall back to the exact search
      if (const auto h = world.CastWalls({px, py}, {dx, dy})) hit.r = h->first, hit.id = h->second;
    }
    hit.surf = hit.id >= 0 ? Surf::kWall : Surf::kNone;
    if (s.k < 0 && s.rk < hit.r) {
      hit.surf = Surf::kFloor;
      hit.r = s.rk;
    } else if (s.k > 0) {
      const double rc = (frame_ceiling - cam_h) * s.rk;
      if (rc < hit.r) {
        hit.surf = Surf::kCeiling;
        hit.r = rc;
      }
    }
    TraceRest(s, dx, dy, hit);
    return hit;
  }

  // Trace's obstacle search and stepped-ceiling correction, for `hit` the nearest wall, floor or
  // ceiling along sample s (horizontal direction dx, dy).
  [[gnu::always_inline]] void TraceRest(const Sample& s, double dx, double dy, Hit& hit) const {
    const int cnt = bin_count[s.bin];
    // An obstacle's entry distance is at least its bounding circle's nearest distance: none
    // in the bin can be met before the hit when the nearest lies beyond it (with a margin).
    if (cnt > 0 && bin_near[s.bin] <= hit.r * (1 + 1e-9) + 1e-9) {
      if (cnt <= kMaxBinObstacles) {
        const int* list = &bin_obs[static_cast<std::size_t>(s.bin) * kMaxBinObstacles];
        for (int i = 0; i < cnt; ++i) HitObstacle(list[i], obs_ox[list[i]], obs_oy[list[i]], cam_h, dx, dy, s.k, hit);
      } else {
        for (std::size_t o = 0; o < world.obstacles.size(); ++o)
          HitObstacle(static_cast<int>(o), obs_ox[o], obs_oy[o], cam_h, dx, dy, s.k, hit);
      }
    }
    if (!uniform_ceiling && hit.surf == Surf::kCeiling) {
      // Ceilings of other heights: re-intersect with the height over the hit point.
      const double h2 = world.CeilingAt({px + dx * hit.r, py + dy * hit.r});
      if (h2 > cam_h && h2 != frame_ceiling) hit.r = (h2 - cam_h) / s.k;
    }
  }

  // The slow path for mirror reflections: any origin, all walls and obstacles.
  Hit TraceFrom(double ox, double oy, double oz, double dx, double dy, double k) const {
    Hit hit;
    if (const auto h = world.CastWalls({ox, oy}, {dx, dy})) {
      hit.surf = Surf::kWall;
      hit.id = h->second;
      hit.r = h->first;
    }
    if (k < 0 && oz / -k < hit.r) hit = {Surf::kFloor, -1, oz / -k, 0, 0, 0};
    const double ceil_h = world.CeilingAt({ox, oy});
    if (k > 0 && (ceil_h - oz) / k < hit.r) hit = {Surf::kCeiling, -1, (ceil_h - oz) / k, 0, 0, 0};
    for (std::size_t o = 0; o < world.obstacles.size(); ++o) {
      const Obstacle& ob = world.obstacles[o];
      const double c = std::cos(ob.yaw), s = std::sin(ob.yaw);
      const double rx = ox - ob.centre.x(), ry = oy - ob.centre.y();
      HitObstacle(static_cast<int>(o), c * rx + s * ry, -s * rx + c * ry, oz, dx, dy, k, hit);
    }
    HitBody(ox, oy, oz, dx, dy, k, hit);
    return hit;
  }

  float Tex(int material, double u, double v) const {
    const detail::TextureTable& t = tex[material];
    const int iu = static_cast<int>(u * t.inv_texel_m + 16777216.0) & (detail::kTexSize - 1);
    const int iv = static_cast<int>(v * t.inv_texel_m + 16777216.0) & (detail::kTexSize - 1);
    return t.texels[iv * detail::kTexSize + iu] * t.gain;
  }

  [[gnu::always_inline]] std::size_t GridIndex(double x, double y) const {
    const int i = std::clamp(static_cast<int>((x - gx0) * (1.0 / kCell)), 0, gnx - 1);
    const int j = std::clamp(static_cast<int>((y - gy0) * (1.0 / kCell)), 0, gny - 1);
    return static_cast<std::size_t>(j) * gnx + i;
  }

  // Irradiance of wall w at `along` (its coordinate along the wall) and height z: the wall's
  // light table, linear along the wall and nearest in height.
  [[gnu::always_inline]] double WallIrradiance(int w, double along, double z) const {
    const WallLight& wl = wall_light[w];
    const double fu = std::clamp((along - wl.lo) * (1.0 / kWallCell), 0.0, wl.fu_max);
    const int iu = static_cast<int>(fu);
    const int iz = std::clamp(static_cast<int>(z * (1.0 / kWallCell) + 0.5), 0, wl.nz - 1);
    const float* col = wl.irr + (iz * wl.nu + iu);
    return col[0] + (fu - iu) * (col[1] - col[0]);
  }

  // Mean of a piecewise-constant table over the box [a0, a1] × [b0, b1] in cell units (clamped to
  // the table, at least 1e-6 cells wide), from its summed-area table `sat` (row stride `stride`,
  // first index a): the integral image is bilinear within each cell.
  [[gnu::always_inline]] static double SatBoxMean(const double* sat, std::size_t stride, int na, int nb, double a0, double a1, double b0, double b1) {
    auto clamp_box = [](double& lo, double& hi, int n) {
      lo = std::clamp(lo, 0.0, static_cast<double>(n));
      hi = std::clamp(hi, 0.0, static_cast<double>(n));
      if (hi - lo < 1e-6) {
        lo = std::min(lo, n - 1e-6);
        hi = lo + 1e-6;
      }
    };
    clamp_box(a0, a1, na);
    clamp_box(b0, b1, nb);
    auto at = [&](double a, double b) {
      const int i = std::min(static_cast<int>(a), na - 1), j = std::min(static_cast<int>(b), nb - 1);
      const double ta = a - i, tb = b - j;
      const double* r0 = sat + static_cast<std::size_t>(i) * stride + j;
      const double* r1 = r0 + stride;
      return (1 - ta) * ((1 - tb) * r0[0] + tb * r0[1]) + ta * ((1 - tb) * r1[0] + tb * r1[1]);
    };
    return (at(a1, b1) - at(a0, b1) - at(a1, b0) + at(a0, b0)) / ((a1 - a0) * (b1 - b0));
  }
  // Mean floor irradiance over [x0, x1] × [y0, y1] (world metres).
  [[gnu::always_inline]] double FloorIrradianceMean(double x0, double x1, double y0, double y1) const {
    const double s = 1.0 / kCell;
    return SatBoxMean(floor_sat.data(), static_cast<std::size_t>(gnx) + 1, gny, gnx, (y0 - gy0) * s, (y1 - gy0) * s,
                      (x0 - gx0) * s, (x1 - gx0) * s);
  }
  // Mean irradiance of wall w over [along0, along1] × [z0, z1] (its table's samples taken as
  // cells centred on them).
  [[gnu::always_inline]] double WallIrradianceMean(int w, double along0, double along1, double z0, double z1) const {
    const WallLight& wl = wall_light[w];
    const double s = 1.0 / kWallCell;
    return SatBoxMean(wall_sat.data() + wl.sat_offset, static_cast<std::size_t>(wl.nz) + 1, wl.nu, wl.nz,
                      (along0 - wl.lo) * s + 0.5, (along1 - wl.lo) * s + 0.5, z0 * s + 0.5, z1 * s + 0.5);
  }

  // Samples on one plain region (no decal, flat item or light panel) of one plane: the sum of
  // their irradiance and the box their texture coordinates span.
  struct PlainAccum {
    double e_sum = 0;
    int count = 0;
    double u_lo = kInf, u_hi = -kInf, v_lo = kInf, v_hi = -kInf;
  };
  void Accumulate(PlainAccum& acc, Surf surf, int wall, double x, double y, double z) const {
    double tu = x, tv = y, e;
    if (surf == Surf::kWall) {
      tu = world.walls[wall].along_x ? x : y;
      tv = z;
      e = WallIrradiance(wall, tu, z);
    } else {
      const double irr = cells[GridIndex(x, y)].irr;
      e = surf == Surf::kCeiling ? world.ambient + kCeilingBounce * irr : irr;
    }
    acc.e_sum += e;
    ++acc.count;
    acc.u_lo = std::min(acc.u_lo, tu), acc.u_hi = std::max(acc.u_hi, tu);
    acc.v_lo = std::min(acc.v_lo, tv), acc.v_hi = std::max(acc.v_hi, tv);
  }
  // The samples' mean radiance with the mean irradiance and the box-filtered texture.
  double AccumRadiance(const PlainAccum& acc, Surf surf, int mat) const {
    const MatFast& m = mats[mat];
    const double e = acc.e_sum / acc.count;
    const bool wall = surf == Surf::kWall;
    return tex[mat].BoxMean(acc.u_lo, acc.u_hi, acc.v_lo, acc.v_hi) * (m.albedo * e + (wall ? m.emission : 0.0)) +
           (wall ? 0.0 : m.emission);
  }

  // What a hit looks like from (ox, oy, oz) along (dx, dy, k), mirrors left out (see Shade).
  [[gnu::always_inline]] SurfPt Describe(const Hit& hit, double ox, double oy, double oz, double dx, double dy, double k) const {
    SurfPt p;
    const bool plane = hit.surf == Surf::kFloor || hit.surf == Surf::kCeiling;  // (their hit.id is stale)
    p.key1 = static_cast<std::uint32_t>(hit.surf) << 24 | (plane ? 0xFFFFFFu : static_cast<std::uint32_t>(hit.id) & 0xFFFFFFu);
    const double x = ox + dx * hit.r, y = oy + dy * hit.r;
    switch (hit.surf) {
      case Surf::kNone:
      case Surf::kInside:
      case Surf::kBody: p.exact = true; return p;  // (the body: reflected rays only, never here)
      case Surf::kFloor: {
        const Cell& cell = cells[GridIndex(x, y)];
        double lx = 0.0, ly = 0.0;
        if (const int i = FlatItemAt(cell, x, y, lx, ly); i >= 0) {
          const FlatItem& it = world.flat_items[i];
          const MatFast& m = mats[it.material];
          p.key2 = static_cast<std::uint32_t>(it.material) << 16 | static_cast<std::uint32_t>(i + 1);
          p.mat = it.material, p.tu = lx, p.tv = ly, p.a = m.albedo * cell.irr, p.b = m.emission;
          return p;
        }
        const int mat = cell.floor_mat;
        const MatFast& m = mats[mat];
        p.key2 = static_cast<std::uint32_t>(mat) << 16;
        p.mat = mat, p.tu = x, p.tv = y, p.a = m.albedo * cell.irr, p.b = m.emission;
        return p;
      }
      case Surf::kCeiling: {
        p.exact = !uniform_ceiling;
        const Cell& cell = cells[GridIndex(x, y)];
        const int l = cell.light;
        if (l >= 0) {
          const Light& lt = world.lights[l];
          if (std::abs(x - lt.centre.x()) <= lt.half_x && std::abs(y - lt.centre.y()) <= lt.half_y) {
            p.key2 = 0xFFFF0000u | (static_cast<std::uint32_t>(l) & 0xFFFFu);
            p.b = lt.on ? kLightPanelRadiance * std::max(0.3, lt.intensity) : kOffPanelRadiance;
            return p;
          }
        }
        const int mat = cell.ceil_mat;
        const MatFast& m = mats[mat];
        p.key2 = static_cast<std::uint32_t>(mat) << 16;
        p.mat = mat, p.tu = x, p.tv = y, p.a = m.albedo * (world.ambient + kCeilingBounce * cell.irr), p.b = m.emission;
        return p;
      }
      case Surf::kWall: {
        const WallSegment& ws = world.walls[hit.id];
        const double along = ws.along_x ? x : y;
        const double z = oz + k * hit.r;
        int mat = ws.material, decal = -1;
        double tu = along, tv = z;
        for (int i = decal_begin[hit.id]; i < decal_end[hit.id]; ++i) {
          const Decal& d = decals[i];
          if (along >= d.lo && along <= d.hi && z >= d.z0 && z <= d.z1) {
            mat = d.material, decal = i;
            tu = along - d.lo;
            tv = d.z1 - z;
            break;
          }
        }
        const double e = WallIrradiance(hit.id, along, z);
        const MatFast& m = mats[mat];
        p.key2 = static_cast<std::uint32_t>(mat) << 16 | static_cast<std::uint32_t>(decal + 1);
        p.mat = mat, p.tu = tu, p.tv = tv, p.a = m.albedo * e + m.emission, p.b = 0;
        p.exact = m.mirror > 0;
        return p;
      }
      case Surf::kObsSide: {
        const Obstacle& ob = world.obstacles[hit.id];
        static constexpr double kFace[4] = {0.95, 0.7, 0.82, 0.6};
        p.key2 = static_cast<std::uint32_t>(hit.face);
        p.mat = ob.material, p.tu = hit.face_u, p.tv = hit.face_v;
        p.a = mats[ob.material].albedo * obs_side_irr[hit.id] * kFace[hit.face & 3];
        p.exact = true;
        return p;
      }
      case Surf::kObsTop: {
        const Obstacle& ob = world.obstacles[hit.id];
        p.mat = ob.material, p.tu = hit.face_u, p.tv = hit.face_v, p.a = mats[ob.material].albedo * obs_top_irr[hit.id];
        p.exact = true;
        return p;
      }
      case Surf::kObsBottom: {
        p.b = mats[world.obstacles[hit.id].material].albedo * world.ambient;
        p.exact = true;
        return p;
      }
    }
    return p;
  }

  double Eval(const SurfPt& p) const { return p.mat >= 0 ? Tex(p.mat, p.tu, p.tv) * p.a + p.b : p.b; }

  // Radiance of a hit seen along (dx, dy, k) from (ox, oy, oz); `depth` limits mirror bounces.
  // The flat item (paper, mat) lying under floor point (x, y) of light-map cell `cell`: its index
  // in world.flat_items and the point in the item's own frame (lx, ly); -1 when there is none.
  // Shared by the one-sample shading and the adaptive path's surface description.
  int FlatItemAt(const Cell& cell, double x, double y, double& lx, double& ly) const {
    const int f = cell.flat;
    if (f == -1) return -1;
    for (std::size_t i = (f >= 0 ? f : 0); i < (f >= 0 ? f + 1 : world.flat_items.size()); ++i) {
      const FlatItem& it = world.flat_items[i];
      const double c = std::cos(it.yaw), s = std::sin(it.yaw);
      lx = c * (x - it.centre.x()) + s * (y - it.centre.y());
      ly = -s * (x - it.centre.x()) + c * (y - it.centre.y());
      if (std::abs(lx) <= it.half_x && std::abs(ly) <= it.half_y) return static_cast<int>(i);
    }
    return -1;
  }

  // Written out for speed (the one-sample path); Describe + Eval give the same radiance, which
  // the adaptive-vs-full supersampling test checks.
  [[gnu::always_inline]] double Shade(const Hit& hit, double ox, double oy, double oz, double dx, double dy, double k, int depth) const {
    const double x = ox + dx * hit.r, y = oy + dy * hit.r;
    switch (hit.surf) {
      case Surf::kNone:
      case Surf::kInside: return 0.0;
      case Surf::kFloor: {
        const std::size_t g = GridIndex(x, y);
        const Cell& cell = cells[g];
        double lx = 0.0, ly = 0.0;
        if (const int i = FlatItemAt(cell, x, y, lx, ly); i >= 0) {
          const FlatItem& it = world.flat_items[i];
          const MatFast& m = mats[it.material];
          return m.albedo * Tex(it.material, lx, ly) * cell.irr + m.emission;
        }
        const int mat = cell.floor_mat;
        const MatFast& m = mats[mat];
        return m.albedo * Tex(mat, x, y) * cell.irr + m.emission;
      }
      case Surf::kCeiling: {
        const std::size_t g = GridIndex(x, y);
        const Cell& cell = cells[g];
        const int l = cell.light;
        if (l >= 0) {
          const Light& lt = world.lights[l];
          if (std::abs(x - lt.centre.x()) <= lt.half_x && std::abs(y - lt.centre.y()) <= lt.half_y)
            return lt.on ? kLightPanelRadiance * std::max(0.3, lt.intensity) : kOffPanelRadiance;
        }
        const int mat = cell.ceil_mat;
        const MatFast& m = mats[mat];
        return m.albedo * Tex(mat, x, y) * (world.ambient + kCeilingBounce * cell.irr) + m.emission;
      }
      case Surf::kWall: {
        const WallSegment& ws = world.walls[hit.id];
        const double along = ws.along_x ? x : y;
        const double z = oz + k * hit.r;
        int mat = ws.material;
        double tu = along, tv = z;
        for (int i = decal_begin[hit.id]; i < decal_end[hit.id]; ++i) {
          const Decal& d = decals[i];
          if (along >= d.lo && along <= d.hi && z >= d.z0 && z <= d.z1) {
            mat = d.material;
            tu = along - d.lo;
            tv = d.z1 - z;
            break;
          }
        }
        const double e = WallIrradiance(hit.id, along, z);
        const MatFast& m = mats[mat];
        const double radiance = m.albedo * Tex(mat, tu, tv) * e + m.emission * Tex(mat, tu, tv);
        if (m.mirror > 0 && depth < 1) return MirrorShade(radiance, m.mirror, hit.id, x, y, z, dx, dy, k, depth);
        return radiance;
      }
      case Surf::kObsSide: {
        const Obstacle& ob = world.obstacles[hit.id];
        static constexpr double kFace[4] = {0.95, 0.7, 0.82, 0.6};
        const MatFast& m = mats[ob.material];
        return m.albedo * Tex(ob.material, hit.face_u, hit.face_v) * obs_side_irr[hit.id] * kFace[hit.face & 3];
      }
      case Surf::kObsTop: {
        const Obstacle& ob = world.obstacles[hit.id];
        const MatFast& m = mats[ob.material];
        return m.albedo * Tex(ob.material, hit.face_u, hit.face_v) * obs_top_irr[hit.id];
      }
      case Surf::kObsBottom: {
        const Obstacle& ob = world.obstacles[hit.id];
        return mats[ob.material].albedo * world.ambient;
      }
      case Surf::kBody: {
        if (hit.face == 1) return body_albedo * body_top_irr;
        // The side: the irradiance table interpolated at the outward normal's azimuth (face_u).
        double f = hit.face_u * (kBodyDirs / (2 * kPi));
        if (f < 0) f += kBodyDirs;
        const int i = std::min(static_cast<int>(f), kBodyDirs - 1);
        return body_albedo * (body_side_irr[i] + (f - i) * (body_side_irr[i + 1] - body_side_irr[i]));
      }
    }
    return 0.0;
  }

  // A mirror's radiance: `radiance` (its own) mixed with the reflection of the ray (dx, dy, k)
  // met at (x, y, z) on wall w. Out of line: Shade is inlined and this recursion must not be.
  [[gnu::noinline]] double MirrorShade(double radiance, double mirror, int w, double x, double y, double z, double dx,
                                       double dy, double k, int depth) const {
    const WallSegment& ws = world.walls[w];
    const double rdx = ws.along_x ? dx : -dx, rdy = ws.along_x ? -dy : dy;
    const double nx = x + ws.normal.x() * 1e-6, ny = y + ws.normal.y() * 1e-6;
    const Hit r = TraceFrom(nx, ny, z, rdx, rdy, k);
    return (1 - mirror) * radiance + mirror * Shade(r, nx, ny, z, rdx, rdy, k, depth + 1);
  }

  // Mean radiance of a pixel's n×n samples, each traced in full.
  double PixelTraced(const Sample* s) const {
    const int nn = n * n;
    double sum = 0;
#ifdef SQUINT_RENDER_SIMD
    // With the vector paths: each sample's nearest wall, floor or ceiling along the bearing table
    // as PixelPlanes finds it (PlanesSimd / PlanesAvx2 with no planes of the pixel's own: Trace's
    // operations lane by lane), then the rest of Trace and the shading one by one.
    if (simd) {
      double sdx[kMaxSamples], sdy[kMaxSamples], sr[kMaxSamples];
      int sid[kMaxSamples], sq[kMaxSamples], count[5] = {0, 0, 0, 0, 0};
      Surf ss[kMaxSamples];
      const std::uint32_t kq[4] = {0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu, 0xFFFFFFFFu};
      const bool pq[5] = {false, false, false, false, false};
      const std::size_t pixel = static_cast<std::size_t>(s - samples.data()) / nn;
      if (avx512 ? PlanesSimd(pixel, true, 0, nullptr, kq, pq, sdx, sdy, sr, sid, ss, sq, count, nullptr)
                 : PlanesAvx2(pixel, true, 0, nullptr, kq, pq, sdx, sdy, sr, sid, ss, sq, count, nullptr)) {
        const int depth = has_mirrors ? 0 : 1;
        for (int i = 0; i < nn; ++i) {
          double dx = sdx[i], dy = sdy[i];
          Hit hit;
          if (sq[i] < 0) {  // a sliver wall inside the bin: Trace in full
            hit = Trace(s[i], dx, dy);
          } else {
            hit.surf = ss[i], hit.id = sid[i], hit.r = sr[i];
            TraceRest(s[i], dx, dy, hit);
          }
          sum += Shade(hit, px, py, cam_h, dx, dy, s[i].k, depth);
        }
        return sum / nn;
      }
    }
#endif
    for (int i = 0; i < nn; ++i, ++s) {
      double dx, dy;
      const Hit hit = Trace(*s, dx, dy);
      sum += Shade(hit, px, py, cam_h, dx, dy, s->k, has_mirrors ? 0 : 1);
    }
    return sum / nn;
  }

  // Mean radiance of a pixel's n×n samples on one plane (`key1` of its corners): no tracing.
  double PixelOnPlane(const Sample* s, std::uint32_t key1) const {
    const int nn = n * n;
    const auto surf = static_cast<Surf>(key1 >> 24);
    const int id = static_cast<int>(key1 & 0xFFFFFFu);
    const int depth = has_mirrors ? 0 : 1;
    // First every sample's distance to the plane (the loop's iterations overlap), then the
    // shading in sample order.
    double sdx[kMaxSamples], sdy[kMaxSamples], sr[kMaxSamples];
    const double ceil_rel = frame_ceiling - cam_h;
    for (int i = 0; i < nn; ++i) {
      const Sample& si = s[i];
      const double dx = cyaw * si.ca - syaw * si.sa, dy = syaw * si.ca + cyaw * si.sa;
      sdx[i] = dx, sdy[i] = dy;
      double r = kInf;
      if (surf == Surf::kFloor && si.k < 0) {
        r = si.rk;
      } else if (surf == Surf::kCeiling && si.k > 0) {
        r = ceil_rel * si.rk;
      } else if (surf == Surf::kWall) {
        r = WallDistance(id, dx, dy);
      }
      sr[i] = r;
    }
    double sum = 0;
#ifdef SQUINT_RENDER_SIMD
    if (simd) {
      double val[kMaxSamples];
      bool done[kMaxSamples];
      const std::size_t pixel = static_cast<std::size_t>(s - samples.data()) / nn;
      if (avx512) ShadeOnPlaneSimd(pixel, surf, id, sdx, sdy, sr, val, done);
      else ShadeOnPlaneAvx2(pixel, surf, id, sdx, sdy, sr, val, done);
      for (int i = 0; i < nn; ++i) {
        if (done[i]) {
          sum += val[i];
          continue;
        }
        Hit hit;
        hit.surf = surf, hit.id = surf == Surf::kWall ? id : -1, hit.r = sr[i];
        if (hit.r == kInf) {
          double tx, ty;
          hit = Trace(s[i], tx, ty);
        }
        sum += Shade(hit, px, py, cam_h, sdx[i], sdy[i], s[i].k, depth);
      }
      return sum / nn;
    }
#endif
    for (int i = 0; i < nn; ++i) {
      Hit hit;
      hit.surf = surf, hit.id = surf == Surf::kWall ? id : -1, hit.r = sr[i];
      if (hit.r == kInf) {  // off the plane after all: trace it
        double tx, ty;
        hit = Trace(s[i], tx, ty);
      }
      sum += Shade(hit, px, py, cam_h, sdx[i], sdy[i], s[i].k, depth);
    }
    return sum / nn;
  }

  // Traces the pixel corners and marks the pixels that hold an edge no corner may see.
  void PrepareAdaptive() {
    const double ceil_rel = frame_ceiling - cam_h;
    const std::size_t nc = corners.size();
    // First the bearing-table walls of every corner ray (a short loop whose iterations overlap:
    // the wall divisions dominate), then the rest of Trace and Describe per corner.
    std::size_t i1 = 0;
#ifdef SQUINT_RENDER_SIMD
    if (avx512) i1 = CornerWallsSimd();
    else if (simd) i1 = CornerWallsAvx2();
#endif
    for (std::size_t i = i1; i < nc; ++i) {
      const Sample& cs = corners[i];
      const double dx = cyaw * cs.ca - syaw * cs.sa, dy = syaw * cs.ca + cyaw * cs.sa;
      const int w0 = edge_wall[cs.bin], w1 = edge_wall[cs.bin + 1];
      const double t0 = WallDistance(w0, dx, dy);
      double r = t0;
      int id = w0;
      if (w1 != w0) {
        const double t1 = WallDistance(w1, dx, dy);
        r = t0 <= t1 ? t0 : t1;
        id = t0 <= t1 ? w0 : w1;
      }
      corner_dx[i] = dx, corner_dy[i] = dy, corner_r[i] = r, corner_id[i] = id;
    }
    for (std::size_t i = 0; i < nc; ++i) {
      // Trace and Describe, written out for the common corner (a wall, floor or ceiling point
      // with no obstacle of its bin nearer, on a plain region); any other corner takes them in full.
      // A plain wall corner's `a` (its lit shade) is left 0: only regions' corners use it.
      const Sample& cs = corners[i];
      const double dx = corner_dx[i], dy = corner_dy[i];
      double r = corner_r[i];
      const int id = corner_id[i];
      // (fields written one by one: a whole SurfPt built on the stack and copied stalls on
      // store forwarding)
      SurfPt& p = corner_pt[i];
      Hit hit;
      if (r != kInf && uniform_ceiling) {
        Surf surf = Surf::kWall;
        if (cs.k < 0 && cs.rk < r) {
          surf = Surf::kFloor, r = cs.rk;
        } else if (cs.k > 0) {
          const double rc = ceil_rel * cs.rk;
          if (rc < r) surf = Surf::kCeiling, r = rc;
        }
        if (bin_count[cs.bin] > 0 && bin_near[cs.bin] <= r * (1 + 1e-9) + 1e-9) goto full;  // as Trace
        const double x = px + dx * r, y = py + dy * r;
        if (surf == Surf::kWall) {
          const WallFast& f = wf[id];
          if (f.decals) {  // (Trace would find this hit again: described in full only)
            hit.surf = Surf::kWall, hit.id = id, hit.r = r;
            goto describe;
          }
          const MatFast& m = mats[f.material];
          const std::uint32_t key1 = static_cast<std::uint32_t>(Surf::kWall) << 24 | (static_cast<std::uint32_t>(id) & 0xFFFFFFu);
          const std::uint32_t key2 = static_cast<std::uint32_t>(f.material) << 16;
          const bool exact = m.mirror > 0;
          p.key1 = key1, p.key2 = key2, p.mat = f.material, p.tu = f.along_x ? x : y, p.tv = cam_h + cs.k * r;
          p.a = 0, p.b = 0, p.exact = exact;
          corner_cls[i] = (static_cast<std::uint64_t>(key1) << 32 | key2) | (exact ? 1ull << 63 : 0);
        } else {
          const Cell& cell = cells[GridIndex(x, y)];
          int mat;
          double a;
          if (surf == Surf::kFloor && cell.flat == -1) {
            mat = cell.floor_mat;
            a = mats[mat].albedo * cell.irr;
          } else if (surf == Surf::kCeiling && cell.light < 0) {
            mat = cell.ceil_mat;
            a = mats[mat].albedo * (world.ambient + kCeilingBounce * cell.irr);
          } else {  // a flat item's or a light panel's cell
            hit.surf = surf, hit.id = id, hit.r = r;
            goto describe;
          }
          const std::uint32_t key1 = static_cast<std::uint32_t>(surf) << 24 | 0xFFFFFFu;
          const std::uint32_t key2 = static_cast<std::uint32_t>(mat) << 16;
          p.key1 = key1, p.key2 = key2, p.mat = mat, p.tu = x, p.tv = y, p.a = a, p.b = mats[mat].emission, p.exact = false;
          corner_cls[i] = static_cast<std::uint64_t>(key1) << 32 | key2;
        }
        corner_r[i] = r;
        corner_tu[i] = p.tu;
        corner_tv[i] = p.tv;
        continue;
      }
    full:
      {
        double tdx, tdy;  // (dx and dy again)
        hit = Trace(cs, tdx, tdy);
      }
    describe:
      corner_r[i] = hit.r;
      p = Describe(hit, px, py, cam_h, dx, dy, cs.k);
      corner_cls[i] = (static_cast<std::uint64_t>(p.key1) << 32 | p.key2) | (p.exact ? 1ull << 63 : 0);
      corner_tu[i] = p.tu;
      corner_tv[i] = p.tv;
    }
    for (int u = 0; u < camera.width; ++u) {
      double t = 0, near = kInf;
      bool any_obstacle = true;
#ifdef SQUINT_RENDER_SIMD
      if (avx512) {
        ColumnBoundsSimd(u, t, near, any_obstacle);
      } else if (simd) {
        ColumnBoundsAvx2(u, t, near, any_obstacle);
      } else
#endif
      {
        for (int e = col_bin_lo[u]; e <= col_bin_hi[u] + 1; ++e) t = std::max(t, edge_t[e]);
        for (int b = col_bin_lo[u]; b <= col_bin_hi[u]; ++b) near = std::min(near, bin_near[b]);
      }
      col_max_t[u] = t;
      col_near[u] = near;
      int* list = &col_obs[static_cast<std::size_t>(u) * kMaxColObstacles];
      int cnt = 0;
      for (int b = col_bin_lo[u]; any_obstacle && b <= col_bin_hi[u] && cnt >= 0; ++b) {
        if (bin_count[b] > kMaxBinObstacles) {
          cnt = -1;
          break;
        }
        for (int i = 0; i < bin_count[b] && cnt >= 0; ++i) {
          const int o = bin_obs[static_cast<std::size_t>(b) * kMaxBinObstacles + i];
          if (std::find(list, list + cnt, o) != list + cnt) continue;
          if (cnt == kMaxColObstacles) cnt = -1;
          else list[cnt++] = o;
        }
      }
      col_nobs[u] = cnt;
    }
    std::fill(mask.begin(), mask.end(), 0);
    const Eigen::Vector2d cam_xy(px, py);
    // Vertical wall edges (the ends of the walls that face the camera).
    for (const WallSegment& ws : world.walls) {
      const double side = ws.along_x ? (py - ws.coord) * ws.normal.y() : (px - ws.coord) * ws.normal.x();
      if (side <= 1e-12) continue;
      for (double a : {ws.lo, ws.hi}) {
        const Eigen::Vector2d e = ws.along_x ? Eigen::Vector2d(a, ws.coord) : Eigen::Vector2d(ws.coord, a);
        if (OutsideWedge(1, &e.x(), &e.y(), 1)) continue;  // would mark no pixel
        MarkSegment(ToCamera(e.x(), e.y(), 0.0), ToCamera(e.x(), e.y(), ws.height_m), (e - cam_xy).norm(), kMaskGeometry);
      }
    }
    // Light panels.
    for (const Light& l : world.lights) {
      const double x0 = l.centre.x() - l.half_x, x1 = l.centre.x() + l.half_x;
      const double y0 = l.centre.y() - l.half_y, y1 = l.centre.y() + l.half_y;
      {
        const double xs[4] = {x0, x1, x1, x0}, ys[4] = {y0, y0, y1, y1};
        if (OutsideWedge(1, xs, ys, 4)) continue;  // would mark no pixel
      }
      const Eigen::Vector3d pts[4] = {ToCamera(x0, y0, l.z_m), ToCamera(x1, y0, l.z_m), ToCamera(x1, y1, l.z_m),
                                      ToCamera(x0, y1, l.z_m)};
      const double near = std::hypot(std::max({x0 - px, px - x1, 0.0}), std::max({y0 - py, py - y1, 0.0}));
      MarkPolygon(pts, 4, near, kMaskPattern);
    }
    // Decals.
    for (const Decal& d : decals) {
      const WallSegment& ws = world.walls[d.wall];
      const double side = ws.along_x ? (py - ws.coord) * ws.normal.y() : (px - ws.coord) * ws.normal.x();
      if (side <= 1e-12) continue;
      {
        const double xs[2] = {ws.along_x ? d.lo : ws.coord, ws.along_x ? d.hi : ws.coord};
        const double ys[2] = {ws.along_x ? ws.coord : d.lo, ws.along_x ? ws.coord : d.hi};
        if (OutsideWedge(1, xs, ys, 2)) continue;  // would mark no pixel
      }
      auto at = [&](double along, double z) {
        return ws.along_x ? ToCamera(along, ws.coord, z) : ToCamera(ws.coord, along, z);
      };
      const Eigen::Vector3d pts[4] = {at(d.lo, d.z0), at(d.hi, d.z0), at(d.hi, d.z1), at(d.lo, d.z1)};
      const double pa = ws.along_x ? px : py;
      const double near = std::hypot(std::max({d.lo - pa, pa - d.hi, 0.0}), side);
      MarkPolygon(pts, 4, near, kMaskPattern);
    }
    // Flat items.
    for (const FlatItem& f : world.flat_items) {
      const double c = std::cos(f.yaw), s = std::sin(f.yaw);
      Eigen::Vector3d pts[4];
      for (int q = 0; q < 4; ++q) {
        const double lx = (q == 1 || q == 2) ? f.half_x : -f.half_x, ly = q >= 2 ? f.half_y : -f.half_y;
        pts[q] = ToCamera(f.centre.x() + c * lx - s * ly, f.centre.y() + s * lx + c * ly, 0.0);
      }
      MarkPolygon(pts, 4, 0.0, kMaskPattern);
    }
  }

#ifdef SQUINT_RENDER_SIMD
  // Column u's farthest bearing-table wall and nearest obstacle (maxima and minima of values
  // that are positive or infinite: the same in any order), eight bins per AVX-512 step, and
  // whether any of its bins lists an obstacle.
  [[gnu::target("avx512f,avx512vl,avx512dq")]] void ColumnBoundsSimd(int u, double& t, double& near, bool& any_obstacle) const {
    const int lo = col_bin_lo[u], hi = col_bin_hi[u];
    __m512d tv = _mm512_setzero_pd(), nv = _mm512_set1_pd(kInf);
    __mmask8 listed = 0;
    for (int e = lo; e <= hi + 1; e += 8) {
      const __mmask8 m = static_cast<__mmask8>(hi + 1 - e >= 7 ? 0xFF : (1u << (hi + 2 - e)) - 1);
      tv = _mm512_mask_max_pd(tv, m, tv, _mm512_maskz_loadu_pd(m, &edge_t[e]));
      const __mmask8 mb = static_cast<__mmask8>(hi - e >= 7 ? 0xFF : (hi < e ? 0 : (1u << (hi + 1 - e)) - 1));
      nv = _mm512_mask_min_pd(nv, mb, nv, _mm512_maskz_loadu_pd(mb, &bin_near[e]));
      listed |= _mm256_mask_cmpgt_epi32_mask(mb, _mm256_maskz_loadu_epi32(mb, &bin_count[e]), _mm256_setzero_si256());
    }
    t = _mm512_reduce_max_pd(tv);
    near = _mm512_reduce_min_pd(nv);
    any_obstacle = listed != 0;
  }
#endif

  // A world point in the camera frame (x right, y down, z along the optical axis).
  Eigen::Vector3d ToCamera(double x, double y, double z) const {
    const double rx = x - px, ry = y - py;
    return cam_R_robot * Eigen::Vector3d(cyaw * rx + syaw * ry, -syaw * rx + cyaw * ry, z - cam_h);
  }

  // Marks with `bit` every pixel that the convex polygon (camera frame, np <= 4 points) may
  // cover, unless walls nearer than `near` (its horizontal distance) hide all of its columns.
  void MarkPolygon(const Eigen::Vector3d* pts, int np, double near, std::uint8_t bit) {
    constexpr double kNear = 1e-3;
    double umin = kInf, umax = -kInf, vmin = kInf, vmax = -kInf;
    auto add = [&](const Eigen::Vector3d& q) {
      const double u = camera.fx * q.x() / q.z() + camera.cx, v = camera.fy * q.y() / q.z() + camera.cy;
      umin = std::min(umin, u), umax = std::max(umax, u), vmin = std::min(vmin, v), vmax = std::max(vmax, v);
    };
    // Clip against the plane z = kNear (Sutherland-Hodgman); a segment when np == 2.
    const int edges = np == 2 ? 1 : np;
    for (int i = 0; i < np; ++i)
      if (pts[i].z() >= kNear) add(pts[i]);
    for (int i = 0; i < edges; ++i) {
      const Eigen::Vector3d& a = pts[i];
      const Eigen::Vector3d& b = pts[(i + 1) % np];
      if ((a.z() < kNear) != (b.z() < kNear)) add(a + (b - a) * ((kNear - a.z()) / (b.z() - a.z())));
    }
    if (umin > umax) return;  // wholly behind the camera
    constexpr double kPad = 1e-3;
    const int u0 = std::max(0, static_cast<int>(std::ceil(std::max(umin - 0.5 - kPad, -1.0))));
    const int u1 = std::min(camera.width - 1, static_cast<int>(std::floor(std::min(umax + 0.5 + kPad, 1e6))));
    const int v0 = std::max(0, static_cast<int>(std::ceil(std::max(vmin - 0.5 - kPad, -1.0))));
    const int v1 = std::min(camera.height - 1, static_cast<int>(std::floor(std::min(vmax + 0.5 + kPad, 1e6))));
    if (u0 > u1 || v0 > v1) return;
    double far = 0;
    for (int u = u0; u <= u1; ++u) far = std::max(far, col_max_t[u]);
    if (near > far * (1 + 1e-6) + 1e-6) return;  // behind the walls in every column it spans
    for (int v = v0; v <= v1; ++v)
      for (int u = u0; u <= u1; ++u) mask[static_cast<std::size_t>(v) * camera.width + u] |= bit;
  }

  // Marks with `bit` every pixel that the segment a-b (camera frame) may cross, row by row: in
  // each pixel row, the columns of the part of its image within the row (padded as MarkPolygon
  // pads), unless walls nearer than `near` hide all of its columns.
  void MarkSegment(Eigen::Vector3d a, Eigen::Vector3d b, double near, std::uint8_t bit) {
    constexpr double kNear = 1e-3, kPad = 1e-3;
    if (a.z() < kNear && b.z() < kNear) return;  // wholly behind the camera
    if (a.z() < kNear) a += (b - a) * ((kNear - a.z()) / (b.z() - a.z()));
    else if (b.z() < kNear) b += (a - b) * ((kNear - b.z()) / (a.z() - b.z()));
    const double ua = camera.fx * a.x() / a.z() + camera.cx, va = camera.fy * a.y() / a.z() + camera.cy;
    const double ub = camera.fx * b.x() / b.z() + camera.cx, vb = camera.fy * b.y() / b.z() + camera.cy;
    const double vmin = std::min(va, vb), vmax = std::max(va, vb);
    const int u0 = std::max(0, static_cast<int>(std::ceil(std::max(std::min(ua, ub) - 0.5 - kPad, -1.0))));
    const int u1 = std::min(camera.width - 1, static_cast<int>(std::floor(std::min(std::max(ua, ub) + 0.5 + kPad, 1e6))));
    const int v0 = std::max(0, static_cast<int>(std::ceil(std::max(vmin - 0.5 - kPad, -1.0))));
    const int v1 = std::min(camera.height - 1, static_cast<int>(std::floor(std::min(vmax + 0.5 + kPad, 1e6))));
    if (u0 > u1 || v0 > v1) return;
    double far = 0;
    for (int u = u0; u <= u1; ++u) far = std::max(far, col_max_t[u]);
    if (near > far * (1 + 1e-6) + 1e-6) return;  // behind the walls in every column it spans
    const double dv = vb - va;
    int v = v0;
#ifdef SQUINT_RENDER_SIMD
    if (avx512 && std::abs(dv) > 1e-9) v = MarkRowsSimd(ua, ub, va, dv, u0, u1, v0, v1, bit);
    else if (simd && std::abs(dv) > 1e-9) v = MarkRowsAvx2(ua, ub, va, dv, u0, u1, v0, v1, bit);
#endif
    for (; v <= v1; ++v) {
      // The segment's columns over rows [v - 0.5 - pad, v + 0.5 + pad] (u is affine in v).
      double lo = std::min(ua, ub), hi = std::max(ua, ub);
      if (std::abs(dv) > 1e-9) {
        const double t0 = std::clamp((v - 0.5 - kPad - va) / dv, 0.0, 1.0), t1 = std::clamp((v + 0.5 + kPad - va) / dv, 0.0, 1.0);
        const double x0 = ua + t0 * (ub - ua), x1 = ua + t1 * (ub - ua);
        lo = std::min(x0, x1), hi = std::max(x0, x1);
      }
      const int c0 = std::max(u0, static_cast<int>(std::ceil(lo - 0.5 - kPad)));
      const int c1 = std::min(u1, static_cast<int>(std::floor(hi + 0.5 + kPad)));
      for (int u = c0; u <= c1; ++u) mask[static_cast<std::size_t>(v) * camera.width + u] |= bit;
    }
  }

#ifdef SQUINT_RENDER_SIMD
  // MarkSegment's rows v0 .. v1 (|dv| > 1e-9), eight rows per AVX-512 step: each row's columns
  // with MarkSegment's operations (std::clamp, std::min and std::max as the selects they are;
  // ceil and floor exact), then its marks. Returns the first row it did not mark.
  [[gnu::target("avx512f,avx512vl,avx512dq")]] int MarkRowsSimd(double ua, double ub, double va, double dv, int u0, int u1, int v0,
                                                               int v1, std::uint8_t bit) {
    constexpr double kPad = 1e-3;
    const __m512d zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1.0);
    const __m512d vav = _mm512_set1_pd(va), dvv = _mm512_set1_pd(dv), uav = _mm512_set1_pd(ua), dua = _mm512_set1_pd(ub - ua);
    int v = v0;
    for (; v + 7 <= v1; v += 8) {
      const __m512d vd = _mm512_cvtepi32_pd(_mm256_add_epi32(_mm256_set1_epi32(v), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7)));
      const __m512d r0 = _mm512_div_pd(_mm512_sub_pd(_mm512_sub_pd(_mm512_sub_pd(vd, _mm512_set1_pd(0.5)), _mm512_set1_pd(kPad)), vav), dvv);
      const __m512d r1 = _mm512_div_pd(_mm512_sub_pd(_mm512_add_pd(_mm512_add_pd(vd, _mm512_set1_pd(0.5)), _mm512_set1_pd(kPad)), vav), dvv);
      // std::clamp(r, 0.0, 1.0): r < 0 ? 0 : (1 < r ? 1 : r)
      const __m512d t0 = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(r0, zero, _CMP_LT_OQ), _mm512_mask_blend_pd(_mm512_cmp_pd_mask(one, r0, _CMP_LT_OQ), r0, one), zero);
      const __m512d t1 = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(r1, zero, _CMP_LT_OQ), _mm512_mask_blend_pd(_mm512_cmp_pd_mask(one, r1, _CMP_LT_OQ), r1, one), zero);
      const __m512d x0 = _mm512_add_pd(uav, _mm512_mul_pd(t0, dua)), x1 = _mm512_add_pd(uav, _mm512_mul_pd(t1, dua));
      const __mmask8 swap = _mm512_cmp_pd_mask(x1, x0, _CMP_LT_OQ);  // std::min(x0, x1) is x1 there, std::max x0
      const __m512d lo = _mm512_mask_blend_pd(swap, x0, x1), hi = _mm512_mask_blend_pd(swap, x1, x0);
      const __m512d cl = _mm512_roundscale_pd(_mm512_sub_pd(_mm512_sub_pd(lo, _mm512_set1_pd(0.5)), _mm512_set1_pd(kPad)), _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC);
      const __m512d fh = _mm512_roundscale_pd(_mm512_add_pd(_mm512_add_pd(hi, _mm512_set1_pd(0.5)), _mm512_set1_pd(kPad)), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
      alignas(32) int c0[8], c1[8];
      _mm256_store_si256(reinterpret_cast<__m256i*>(c0), _mm256_max_epi32(_mm256_set1_epi32(u0), _mm512_cvttpd_epi32(cl)));
      _mm256_store_si256(reinterpret_cast<__m256i*>(c1), _mm256_min_epi32(_mm256_set1_epi32(u1), _mm512_cvttpd_epi32(fh)));
      for (int k = 0; k < 8; ++k)
        for (int u = c0[k]; u <= c1[k]; ++u) mask[static_cast<std::size_t>(v + k) * camera.width + u] |= bit;
    }
    return v;
  }
#endif

  // Distance along a sample (horizontal direction dx, dy) to the plane `key1` (infinity when the
  // sample does not meet it, for a wall within its extent).
  double PlaneDistance(std::uint32_t key1, const Sample& s, double dx, double dy) const {
    switch (static_cast<Surf>(key1 >> 24)) {
      case Surf::kFloor: return s.k < 0 ? s.rk : kInf;
      case Surf::kCeiling: return s.k > 0 ? (frame_ceiling - cam_h) * s.rk : kInf;
      case Surf::kWall: return WallDistance(static_cast<int>(key1 & 0xFFFFFFu), dx, dy);
      default: return kInf;
    }
  }

#ifdef SQUINT_RENDER_SIMD
  // WallDistance for eight walls (w, -1 for none) and directions, lane by lane.
  // WallDistance for eight directions from a wall's fields (each lane its wall's), lane by lane.
  [[gnu::target("avx512f,avx512vl,avx512dq"), gnu::always_inline]] static inline __m512d WallDistance8(__m512d off, __m512d sx, __m512d syy,
                                                                                                     __m512d base, __m512d lo, __m512d hi,
                                                                                                     __m512d dx, __m512d dy) {
    const __m512d t = _mm512_div_pd(off, _mm512_add_pd(_mm512_mul_pd(sx, dx), _mm512_mul_pd(syy, dy)));
    const __m512d along = _mm512_add_pd(base, _mm512_mul_pd(t, _mm512_add_pd(_mm512_mul_pd(syy, dx), _mm512_mul_pd(sx, dy))));
    const __mmask8 ok = _mm512_cmp_pd_mask(t, _mm512_setzero_pd(), _CMP_GT_OQ) & _mm512_cmp_pd_mask(along, lo, _CMP_GE_OQ) &
                        _mm512_cmp_pd_mask(along, hi, _CMP_LE_OQ);
    return _mm512_mask_blend_pd(ok, _mm512_set1_pd(kInf), t);
  }
  // ... for one wall w (its fields broadcast, no gathers).
  [[gnu::target("avx512f,avx512vl,avx512dq"), gnu::always_inline]] inline __m512d WallDistance8(int w, __m512d dx, __m512d dy) const {
    const WallFast& f = wf[w];
    return WallDistance8(_mm512_set1_pd(f.off), _mm512_set1_pd(f.sx), _mm512_set1_pd(f.sy), _mm512_set1_pd(f.base),
                         _mm512_set1_pd(f.lo), _mm512_set1_pd(f.hi), dx, dy);
  }
  // ... for eight walls (w, -1 for none): one wall's fields broadcast when all lanes name it, else gathered.
  [[gnu::target("avx512f,avx512vl,avx512dq"), gnu::always_inline]] inline __m512d WallDistance8(__m256i w, __m512d dx, __m512d dy) const {
    const int w_first = _mm256_cvtsi256_si32(w);
    if (_mm256_cmpeq_epi32_mask(w, _mm256_set1_epi32(w_first)) == 0xFF) return WallDistance8(w_first, dx, dy);
    static_assert(sizeof(WallFast) % sizeof(double) == 0);
    constexpr int kWfStride = sizeof(WallFast) / sizeof(double);
    const double* wfb = reinterpret_cast<const double*>(wall_fast.data());
    constexpr int kOff = offsetof(WallFast, off) / 8, kSx = offsetof(WallFast, sx) / 8, kSy = offsetof(WallFast, sy) / 8,
                  kBase = offsetof(WallFast, base) / 8, kLo = offsetof(WallFast, lo) / 8, kHi = offsetof(WallFast, hi) / 8;
    const __m256i idx = _mm256_mullo_epi32(_mm256_add_epi32(w, _mm256_set1_epi32(1)), _mm256_set1_epi32(kWfStride));
    const __m512d off = _mm512_i32gather_pd(idx, wfb + kOff, 8), sx = _mm512_i32gather_pd(idx, wfb + kSx, 8);
    const __m512d syy = _mm512_i32gather_pd(idx, wfb + kSy, 8), base = _mm512_i32gather_pd(idx, wfb + kBase, 8);
    const __m512d lo = _mm512_i32gather_pd(idx, wfb + kLo, 8), hi = _mm512_i32gather_pd(idx, wfb + kHi, 8);
    return WallDistance8(off, sx, syy, base, lo, hi, dx, dy);
  }

  // PrepareAdaptive's first loop (each corner ray's direction and nearest bearing-table wall),
  // eight corners per AVX-512 step with its operations lane by lane. Returns the corners done.
  [[gnu::target("avx512f,avx512vl,avx512dq")]] std::size_t CornerWallsSimd() {
    const std::size_t nc = corners.size();
    const __m512d cy = _mm512_set1_pd(cyaw), sy = _mm512_set1_pd(syaw);
    std::size_t i = 0;
    for (; i + 8 <= nc; i += 8) {
      const __m512d ca = _mm512_cvtps_pd(_mm256_loadu_ps(&corner_ca[i])), sa = _mm512_cvtps_pd(_mm256_loadu_ps(&corner_sa[i]));
      const __m512d dx = _mm512_sub_pd(_mm512_mul_pd(cy, ca), _mm512_mul_pd(sy, sa));
      const __m512d dy = _mm512_add_pd(_mm512_mul_pd(sy, ca), _mm512_mul_pd(cy, sa));
      const __m256i bin = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&corner_bin[i]));
      const __m256i w0 = _mm256_i32gather_epi32(edge_wall.data(), bin, 4), w1 = _mm256_i32gather_epi32(edge_wall.data() + 1, bin, 4);
      const __mmask8 same = _mm256_cmpeq_epi32_mask(w0, w1);
      const __m512d t0 = WallDistance8(w0, dx, dy);
      const __m512d t1 = same == 0xFF ? t0 : WallDistance8(w1, dx, dy);
      const __mmask8 first = same | _mm512_cmp_pd_mask(t0, t1, _CMP_LE_OQ);  // (w1 == w0: w0 and t0)
      _mm512_storeu_pd(&corner_dx[i], dx);
      _mm512_storeu_pd(&corner_dy[i], dy);
      _mm512_storeu_pd(&corner_r[i], _mm512_mask_blend_pd(first, t1, t0));
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(&corner_id[i]), _mm256_mask_blend_epi32(first, w1, w0));
    }
    return i;
  }

  // GridIndex for eight floor points, in floats from the start of `cells` (the cell's words).
  [[gnu::target("avx512f,avx512vl,avx512dq"), gnu::always_inline]] inline __m256i GridWord8(__m512d x, __m512d y) const {
    static_assert(sizeof(Cell) % sizeof(float) == 0);
    constexpr int kCellStride = sizeof(Cell) / sizeof(float);
    __m256i gi = _mm512_cvttpd_epi32(_mm512_mul_pd(_mm512_sub_pd(x, _mm512_set1_pd(gx0)), _mm512_set1_pd(1.0 / kCell)));
    __m256i gj = _mm512_cvttpd_epi32(_mm512_mul_pd(_mm512_sub_pd(y, _mm512_set1_pd(gy0)), _mm512_set1_pd(1.0 / kCell)));
    gi = _mm256_min_epi32(_mm256_max_epi32(gi, _mm256_setzero_si256()), _mm256_set1_epi32(gnx - 1));
    gj = _mm256_min_epi32(_mm256_max_epi32(gj, _mm256_setzero_si256()), _mm256_set1_epi32(gny - 1));
    return _mm256_mullo_epi32(_mm256_add_epi32(_mm256_mullo_epi32(gj, _mm256_set1_epi32(gnx)), gi), _mm256_set1_epi32(kCellStride));
  }

  // WallIrradiance for eight points (along, z) of the wall lit by `wl` (lanes outside m read
  // nothing).
  [[gnu::target("avx512f,avx512vl,avx512dq"), gnu::always_inline]] inline __m512d WallIrradiance8(const WallLight& wl, __m512d along,
                                                                                                __m512d z, __mmask8 m) const {
    const __m512d zero = _mm512_setzero_pd(), wall_s = _mm512_set1_pd(1.0 / kWallCell), fmax = _mm512_set1_pd(wl.fu_max);
    __m512d fu = _mm512_mul_pd(_mm512_sub_pd(along, _mm512_set1_pd(wl.lo)), wall_s);
    fu = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(fu, zero, _CMP_LT_OQ), fu, zero);
    fu = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(fmax, fu, _CMP_LT_OQ), fu, fmax);
    const __m256i iu = _mm512_cvttpd_epi32(fu);
    __m256i iz = _mm512_cvttpd_epi32(_mm512_add_pd(_mm512_mul_pd(z, wall_s), _mm512_set1_pd(0.5)));
    iz = _mm256_min_epi32(_mm256_max_epi32(iz, _mm256_setzero_si256()), _mm256_set1_epi32(wl.nz - 1));
    const __m256i cell = _mm256_add_epi32(_mm256_mullo_epi32(iz, _mm256_set1_epi32(wl.nu)), iu);
    const __m256 c0 = _mm256_mmask_i32gather_ps(_mm256_setzero_ps(), m, cell, wl.irr, 4);
    const __m256 c1 = _mm256_mmask_i32gather_ps(_mm256_setzero_ps(), m, cell, wl.irr + 1, 4);
    return _mm512_add_pd(_mm512_cvtps_pd(c0), _mm512_mul_pd(_mm512_sub_pd(fu, _mm512_cvtepi32_pd(iu)), _mm512_cvtps_pd(_mm256_sub_ps(c1, c0))));
  }

  // PixelPlanes' first two passes for pixel `pixel` (n * n a multiple of 8), eight samples per
  // AVX-512 step: each sample's hit and slot (sdx .. sq, count) and each plain plane's sums (acc),
  // with the scalar code's operations per lane. false: the pixel must be traced in full.
  [[gnu::target("avx512f,avx512vl,avx512dq")]] bool PlanesSimd(std::size_t pixel, bool by_bins, int np, const std::uint32_t* keys,
                                                              const std::uint32_t* kq, const bool* pq, double* sdx, double* sdy,
                                                              double* sr, int* sid, Surf* ss, int* sq, int* count,
                                                              PlainAccum* acc) const {
    const int nn = n * n;
    const float* soa = &sample_soa[pixel * nn * 4];
    const std::int32_t* bins_p = &sample_bin[pixel * nn];
    const __m512d cy = _mm512_set1_pd(cyaw), sy = _mm512_set1_pd(syaw), inf = _mm512_set1_pd(kInf), zero = _mm512_setzero_pd();
    const __m512d ceil_rel = _mm512_set1_pd(frame_ceiling - cam_h);
    const __m256i floor_key = _mm256_set1_epi32(static_cast<int>(static_cast<std::uint32_t>(Surf::kFloor) << 24 | 0xFFFFFFu));
    const __m256i ceil_key = _mm256_set1_epi32(static_cast<int>(static_cast<std::uint32_t>(Surf::kCeiling) << 24 | 0xFFFFFFu));
    for (int i0 = 0; i0 < nn; i0 += 8) {
      const __m512d ca = _mm512_cvtps_pd(_mm256_loadu_ps(soa + i0)), sa = _mm512_cvtps_pd(_mm256_loadu_ps(soa + nn + i0));
      const __m512d k = _mm512_cvtps_pd(_mm256_loadu_ps(soa + 2 * nn + i0)), rk = _mm512_cvtps_pd(_mm256_loadu_ps(soa + 3 * nn + i0));
      const __m512d dx = _mm512_sub_pd(_mm512_mul_pd(cy, ca), _mm512_mul_pd(sy, sa));
      const __m512d dy = _mm512_add_pd(_mm512_mul_pd(sy, ca), _mm512_mul_pd(cy, sa));
      _mm512_storeu_pd(sdx + i0, dx);
      _mm512_storeu_pd(sdy + i0, dy);
      __m512d r;
      __m256i id, key, surf;
      __mmask8 traced = 0;  // (by_bins) a sliver wall inside the bin: trace the sample
      if (by_bins) {
        const __m256i bin = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(bins_p + i0));
        const __m256i w0 = _mm256_i32gather_epi32(edge_wall.data(), bin, 4);
        const __m256i w1 = _mm256_i32gather_epi32(edge_wall.data() + 1, bin, 4);
        const __m512d t0 = WallDistance8(w0, dx, dy);
        const __m512d t1 = _mm256_cmpeq_epi32_mask(w0, w1) == 0xFF ? t0 : WallDistance8(w1, dx, dy);
        // w1 == w0 gives t1 == t0 bit for bit: the selection then keeps w0 and t0, as the scalar code does.
        const __mmask8 first = _mm512_cmp_pd_mask(t0, t1, _CMP_LE_OQ);
        id = _mm256_mask_blend_epi32(first, w1, w0);
        r = _mm512_mask_blend_pd(first, t1, t0);
        traced = _mm512_cmp_pd_mask(r, inf, _CMP_EQ_OQ);
        const __m512d rc = _mm512_mul_pd(ceil_rel, rk);
        const __mmask8 fl = _mm512_cmp_pd_mask(k, zero, _CMP_LT_OQ) & _mm512_cmp_pd_mask(rk, r, _CMP_LT_OQ);
        const __mmask8 ce = static_cast<__mmask8>(~fl) & _mm512_cmp_pd_mask(k, zero, _CMP_GT_OQ) & _mm512_cmp_pd_mask(rc, r, _CMP_LT_OQ);
        r = _mm512_mask_blend_pd(fl, r, rk);
        r = _mm512_mask_blend_pd(ce, r, rc);
        surf = _mm256_set1_epi32(static_cast<int>(Surf::kWall));
        surf = _mm256_mask_blend_epi32(fl, surf, _mm256_set1_epi32(static_cast<int>(Surf::kFloor)));
        surf = _mm256_mask_blend_epi32(ce, surf, _mm256_set1_epi32(static_cast<int>(Surf::kCeiling)));
        key = _mm256_or_si256(_mm256_slli_epi32(_mm256_set1_epi32(static_cast<int>(Surf::kWall)), 24), id);
        key = _mm256_mask_blend_epi32(fl, key, floor_key);
        key = _mm256_mask_blend_epi32(ce, key, ceil_key);
      } else {
        r = inf;
        key = _mm256_setzero_si256();
        for (int q = 0; q < np; ++q) {
          __m512d rq;
          switch (static_cast<Surf>(keys[q] >> 24)) {
            case Surf::kFloor: rq = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(k, zero, _CMP_LT_OQ), inf, rk); break;
            case Surf::kCeiling: rq = _mm512_mask_blend_pd(_mm512_cmp_pd_mask(k, zero, _CMP_GT_OQ), inf, _mm512_mul_pd(ceil_rel, rk)); break;
            case Surf::kWall: rq = WallDistance8(static_cast<int>(keys[q] & 0xFFFFFFu), dx, dy); break;
            default: rq = inf; break;
          }
          const __mmask8 nearer = _mm512_cmp_pd_mask(rq, r, _CMP_LT_OQ);
          r = _mm512_mask_blend_pd(nearer, r, rq);
          key = _mm256_mask_blend_epi32(nearer, key, _mm256_set1_epi32(static_cast<int>(keys[q])));
        }
        if (_mm512_cmp_pd_mask(r, inf, _CMP_EQ_OQ)) return false;
        surf = _mm256_srli_epi32(key, 24);
        const __mmask8 wall = _mm256_cmpeq_epi32_mask(surf, _mm256_set1_epi32(static_cast<int>(Surf::kWall)));
        id = _mm256_mask_blend_epi32(wall, _mm256_set1_epi32(-1), _mm256_and_si256(key, _mm256_set1_epi32(0xFFFFFF)));
      }
      if (!uniform_ceiling &&
          (_mm256_cmpeq_epi32_mask(surf, _mm256_set1_epi32(static_cast<int>(Surf::kCeiling))) & static_cast<__mmask8>(~traced)))
        return false;
      __m256i q = _mm256_set1_epi32(4);
      for (int c = 3; c >= 0; --c) q = _mm256_mask_blend_epi32(_mm256_cmpeq_epi32_mask(key, _mm256_set1_epi32(static_cast<int>(kq[c]))), q, _mm256_set1_epi32(c));
      for (int c = 0; c < 4; ++c)
        if (!pq[c]) q = _mm256_mask_blend_epi32(_mm256_cmpeq_epi32_mask(q, _mm256_set1_epi32(c)), q, _mm256_set1_epi32(4));
      q = _mm256_mask_blend_epi32(traced, q, _mm256_set1_epi32(-1));
      _mm512_storeu_pd(sr + i0, r);
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(sid + i0), id);
      _mm256_storeu_si256(reinterpret_cast<__m256i*>(sq + i0), q);
      _mm_storel_epi64(reinterpret_cast<__m128i*>(ss + i0), _mm256_cvtepi32_epi8(surf));
      static_assert(sizeof(Surf) == 1);
      for (int c = 0; c < 5; ++c) count[c] += __builtin_popcount(_mm256_cmpeq_epi32_mask(q, _mm256_set1_epi32(c)));
      count[4] += __builtin_popcount(traced);
    }
    // Each plain plane's samples: light-map values lane by lane, summed in sample order (packed
    // in that order, the plane's samples only, so that the sum takes no branch per sample).
    double e[kMaxSamples + 8];
    for (int qq = 0; qq < np; ++qq) {
      if (count[qq] == 0) continue;
      PlainAccum& a = acc[qq];
      const auto psurf = static_cast<Surf>(keys[qq] >> 24);
      int ne = 0;
      __m512d u_lo = inf, u_hi = _mm512_set1_pd(-kInf), v_lo = inf, v_hi = _mm512_set1_pd(-kInf);
      const __m512d pxv = _mm512_set1_pd(px), pyv = _mm512_set1_pd(py);
      for (int i0 = 0; i0 < nn; i0 += 8) {
        const __mmask8 m = _mm256_cmpeq_epi32_mask(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(sq + i0)), _mm256_set1_epi32(qq));
        if (!m) continue;
        const __m512d r = _mm512_loadu_pd(sr + i0);
        const __m512d x = _mm512_add_pd(pxv, _mm512_mul_pd(_mm512_loadu_pd(sdx + i0), r));
        const __m512d y = _mm512_add_pd(pyv, _mm512_mul_pd(_mm512_loadu_pd(sdy + i0), r));
        __m512d ev, tu, tv;
        if (psurf == Surf::kWall) {
          const int wid = static_cast<int>(keys[qq] & 0xFFFFFFu);
          const WallLight& wl = wall_light[wid];
          const __m512d k = _mm512_cvtps_pd(_mm256_loadu_ps(soa + 2 * nn + i0));
          const __m512d z = _mm512_add_pd(_mm512_set1_pd(cam_h), _mm512_mul_pd(k, r));
          tu = wf[wid].along_x ? x : y;
          tv = z;
          ev = WallIrradiance8(wl, tu, z, m);
        } else {
          tu = x;
          tv = y;
          const __m256i gidx = GridWord8(x, y);
          const __m512d irr = _mm512_cvtps_pd(_mm256_mmask_i32gather_ps(_mm256_setzero_ps(), m, gidx, &cells[0].irr, 4));
          ev = psurf == Surf::kCeiling ? _mm512_add_pd(_mm512_set1_pd(world.ambient), _mm512_mul_pd(_mm512_set1_pd(kCeilingBounce), irr)) : irr;
        }
        _mm512_storeu_pd(e + ne, _mm512_maskz_compress_pd(m, ev));
        ne += __builtin_popcount(m);
        u_lo = _mm512_mask_min_pd(u_lo, m, u_lo, tu), u_hi = _mm512_mask_max_pd(u_hi, m, u_hi, tu);
        v_lo = _mm512_mask_min_pd(v_lo, m, v_lo, tv), v_hi = _mm512_mask_max_pd(v_hi, m, v_hi, tv);
      }
      double e_sum = 0;
      for (int i = 0; i < ne; ++i) e_sum += e[i];
      a.e_sum = e_sum;
      a.u_lo = _mm512_reduce_min_pd(u_lo), a.u_hi = _mm512_reduce_max_pd(u_hi);
      a.v_lo = _mm512_reduce_min_pd(v_lo), a.v_hi = _mm512_reduce_max_pd(v_hi);
      a.count = count[qq];
    }
    return true;
  }
#endif

#ifdef SQUINT_RENDER_SIMD
  // PixelSplit's samples, eight per AVX-512 step (n * n a multiple of 8): each sample's
  // direction and side of the line from the corners (g, gx, gy, gz), its point on that side's
  // plane, the light map there (summed in sample order) and the texture box. Returns how many
  // lie on the floor or ceiling plane.
  [[gnu::target("avx512f,avx512vl,avx512dq")]] int SplitSimd(const double* g, const double* gx, const double* gy, const double* gz,
                                                            double h_rel, int w, bool along_x, double& pu_lo, double& pu_hi,
                                                            double& pv_lo, double& pv_hi, double& pe, double& wu_lo,
                                                            double& wu_hi, double& wv_lo, double& wv_hi, double& we) const {
    const int nn = n * n;
    const WallSegment& ws = world.walls[w];
    const WallLight& wl = wall_light[w];
    const double wall_c = ws.coord, wall_p = along_x ? py : px, wall_a = along_x ? px : py;
    const __m512d zero = _mm512_setzero_pd(), inf = _mm512_set1_pd(kInf), ninf = _mm512_set1_pd(-kInf);
    const __m512d g0 = _mm512_set1_pd(g[0]), g20 = _mm512_set1_pd(g[2] - g[0]), g1 = _mm512_set1_pd(g[1]), g31 = _mm512_set1_pd(g[3] - g[1]);
    const __m512d x0 = _mm512_set1_pd(gx[0]), x20 = _mm512_set1_pd(gx[2] - gx[0]), x1 = _mm512_set1_pd(gx[1]), x31 = _mm512_set1_pd(gx[3] - gx[1]);
    const __m512d y0 = _mm512_set1_pd(gy[0]), y20 = _mm512_set1_pd(gy[2] - gy[0]), y1 = _mm512_set1_pd(gy[1]), y31 = _mm512_set1_pd(gy[3] - gy[1]);
    const __m512d z0 = _mm512_set1_pd(gz[0]), z20 = _mm512_set1_pd(gz[2] - gz[0]), z1 = _mm512_set1_pd(gz[1]), z31 = _mm512_set1_pd(gz[3] - gz[1]);
    const __m512d hv = _mm512_set1_pd(h_rel), pxv = _mm512_set1_pd(px), pyv = _mm512_set1_pd(py), camz = _mm512_set1_pd(cam_h);
    const __m512d wcp = _mm512_set1_pd(wall_c - wall_p), wav = _mm512_set1_pd(wall_a);
    __m512d pul = inf, puh = ninf, pvl = inf, pvh = ninf, wul = inf, wuh = ninf, wvl = inf, wvh = ninf;
    double pev[kMaxSamples + 8], wev[kMaxSamples + 8];  // each side's light-map values, packed in sample order
    int on_plane = 0, off_plane = 0;
    for (int i0 = 0; i0 < nn; i0 += 8) {
      const __m512d fx = _mm512_loadu_pd(&split_fx[i0]), fy = _mm512_loadu_pd(&split_fy[i0]);
      // Per row (fy) the left and right ends, then along the row (fx), as the scalar loop steps.
      const __m512d g_l = _mm512_add_pd(g0, _mm512_mul_pd(fy, g20)), g_r = _mm512_add_pd(g1, _mm512_mul_pd(fy, g31));
      const __m512d x_l = _mm512_add_pd(x0, _mm512_mul_pd(fy, x20)), x_r = _mm512_add_pd(x1, _mm512_mul_pd(fy, x31));
      const __m512d y_l = _mm512_add_pd(y0, _mm512_mul_pd(fy, y20)), y_r = _mm512_add_pd(y1, _mm512_mul_pd(fy, y31));
      const __m512d z_l = _mm512_add_pd(z0, _mm512_mul_pd(fy, z20)), z_r = _mm512_add_pd(z1, _mm512_mul_pd(fy, z31));
      const __m512d sdx = _mm512_add_pd(x_l, _mm512_mul_pd(fx, _mm512_sub_pd(x_r, x_l)));
      const __m512d sdy = _mm512_add_pd(y_l, _mm512_mul_pd(fx, _mm512_sub_pd(y_r, y_l)));
      const __m512d sdz = _mm512_add_pd(z_l, _mm512_mul_pd(fx, _mm512_sub_pd(z_r, z_l)));
      const __mmask8 on = _mm512_cmp_pd_mask(_mm512_add_pd(g_l, _mm512_mul_pd(fx, _mm512_sub_pd(g_r, g_l))), zero, _CMP_GT_OQ);
      const __mmask8 off = static_cast<__mmask8>(~on);

      if (on) {  // the floor or ceiling plane
        const __m512d t = _mm512_div_pd(hv, sdz);
        const __m512d x = _mm512_add_pd(pxv, _mm512_mul_pd(t, sdx)), y = _mm512_add_pd(pyv, _mm512_mul_pd(t, sdy));
        pul = _mm512_mask_min_pd(pul, on, pul, x), puh = _mm512_mask_max_pd(puh, on, puh, x);
        pvl = _mm512_mask_min_pd(pvl, on, pvl, y), pvh = _mm512_mask_max_pd(pvh, on, pvh, y);
        const __m256i gidx = GridWord8(x, y);
        _mm512_storeu_pd(pev + on_plane, _mm512_maskz_compress_pd(on, _mm512_cvtps_pd(_mm256_mmask_i32gather_ps(_mm256_setzero_ps(), on, gidx, &cells[0].irr, 4))));
        on_plane += __builtin_popcount(on);
      }
      if (off) {  // the wall
        const __m512d across = along_x ? sdy : sdx, other = along_x ? sdx : sdy;
        const __m512d t = _mm512_div_pd(wcp, across);
        const __m512d along = _mm512_add_pd(wav, _mm512_mul_pd(t, other)), z = _mm512_add_pd(camz, _mm512_mul_pd(t, sdz));
        wul = _mm512_mask_min_pd(wul, off, wul, along), wuh = _mm512_mask_max_pd(wuh, off, wuh, along);
        wvl = _mm512_mask_min_pd(wvl, off, wvl, z), wvh = _mm512_mask_max_pd(wvh, off, wvh, z);
        _mm512_storeu_pd(wev + off_plane, _mm512_maskz_compress_pd(off, WallIrradiance8(wl, along, z, off)));
        off_plane += __builtin_popcount(off);
      }
    }
    double pe_sum = 0, we_sum = 0;
    for (int i = 0; i < on_plane; ++i) pe_sum += pev[i];
    for (int i = 0; i < off_plane; ++i) we_sum += wev[i];
    pe = pe_sum, we = we_sum;
    pu_lo = _mm512_reduce_min_pd(pul), pu_hi = _mm512_reduce_max_pd(puh), pv_lo = _mm512_reduce_min_pd(pvl), pv_hi = _mm512_reduce_max_pd(pvh);
    wu_lo = _mm512_reduce_min_pd(wul), wu_hi = _mm512_reduce_max_pd(wuh), wv_lo = _mm512_reduce_min_pd(wvl), wv_hi = _mm512_reduce_max_pd(wvh);
    return on_plane;
  }
#endif

#ifdef SQUINT_RENDER_SIMD
  // Tex(mat, u, v) of eight samples, with their materials' albedo and emission (lanes outside ok
  // read nothing and give 0).
  [[gnu::target("avx512f,avx512vl,avx512dq"), gnu::always_inline]] inline void TexMaterialSimd(
      __m256i mat, __m512d u, __m512d v, __mmask8 ok, __m512d& texv, __m512d& albedo, __m512d& emission) const {
    const __m512d big = _mm512_set1_pd(16777216.0), zero = _mm512_setzero_pd();
    const __m256i m127 = _mm256_set1_epi32(detail::kTexSize - 1);
    const double* mb = reinterpret_cast<const double*>(mats.data());
    const float* tfb = reinterpret_cast<const float*>(texels_fast.data());
    static_assert(sizeof(TexelsFast) == 16);
    // One material in every lane read (the common case): its fields broadcast instead of gathered.
    const int m_first = ok ? _mm256_cvtsi256_si32(_mm256_permutexvar_epi32(_mm256_set1_epi32(__builtin_ctz(ok)), mat)) : 0;
    if (ok && !_mm256_mask_cmpneq_epi32_mask(ok, mat, _mm256_set1_epi32(m_first))) {
      const TexelsFast& t = texels_fast[m_first];
      const __m512d inv = _mm512_set1_pd(t.inv_texel_m);
      const __m256i iu = _mm256_and_si256(_mm512_cvttpd_epi32(_mm512_add_pd(_mm512_mul_pd(u, inv), big)), m127);
      const __m256i iv = _mm256_and_si256(_mm512_cvttpd_epi32(_mm512_add_pd(_mm512_mul_pd(v, inv), big)), m127);
      const __m256i texel = _mm256_and_si256(
          _mm256_mmask_i32gather_epi32(_mm256_setzero_si256(), ok, _mm256_add_epi32(_mm256_slli_epi32(iv, 7), iu), t.texels, 1),
          _mm256_set1_epi32(0xFF));
      texv = _mm512_cvtps_pd(_mm256_mul_ps(_mm256_cvtepi32_ps(texel), _mm256_set1_ps(t.gain)));
      albedo = _mm512_set1_pd(mats[m_first].albedo);
      emission = _mm512_set1_pd(mats[m_first].emission);
      return;
    }
    const __m256i m4 = _mm256_slli_epi32(mat, 2);
    const __m512d inv = _mm512_cvtps_pd(_mm256_mmask_i32gather_ps(_mm256_setzero_ps(), ok, m4, tfb + 2, 4));
    const __m256 gain = _mm256_mmask_i32gather_ps(_mm256_setzero_ps(), ok, m4, tfb + 3, 4);
    const __m512i tp = _mm512_mask_i32gather_epi64(_mm512_setzero_si512(), ok, _mm256_slli_epi32(mat, 1), texels_fast.data(), 8);
    const __m256i iu = _mm256_and_si256(_mm512_cvttpd_epi32(_mm512_add_pd(_mm512_mul_pd(u, inv), big)), m127);
    const __m256i iv = _mm256_and_si256(_mm512_cvttpd_epi32(_mm512_add_pd(_mm512_mul_pd(v, inv), big)), m127);
    const __m512i addr = _mm512_add_epi64(tp, _mm512_cvtepi32_epi64(_mm256_add_epi32(_mm256_slli_epi32(iv, 7), iu)));
    const __m256i texel = _mm256_and_si256(_mm512_mask_i64gather_epi32(_mm256_setzero_si256(), ok, addr, nullptr, 1), _mm256_set1_epi32(0xFF));
    texv = _mm512_cvtps_pd(_mm256_mul_ps(_mm256_cvtepi32_ps(texel), gain));
    const __m256i m3 = _mm256_mullo_epi32(mat, _mm256_set1_epi32(3));
    albedo = _mm512_mask_i32gather_pd(zero, ok, m3, mb + offsetof(MatFast, albedo) / 8, 8);
    emission = _mm512_mask_i32gather_pd(zero, ok, m3, mb + offsetof(MatFast, emission) / 8, 8);
  }

  // PixelOnPlane's shading, eight samples per AVX-512 step, for the samples that Shade would
  // shade without a branch of its own: on the plane (finite r), the floor outside flat items,
  // the ceiling (its light panels tested as Shade does), a wall that is no mirror (its decals
  // tested in order).
  // val[i]: Shade's radiance where done[i]; the others are left to Shade. (sdx, sdy, sr are
  // only read: non-const so that GCC 12 does not take them for uninitialised.)
  [[gnu::target("avx512f,avx512vl,avx512dq")]] void ShadeOnPlaneSimd(std::size_t pixel, Surf surf, int id, double* sdx,
                                                                    double* sdy, double* sr, double* val,
                                                                    bool* done) const {
    const int nn = n * n;
    const float* soa = &sample_soa[pixel * nn * 4];
    const __m512d inf = _mm512_set1_pd(kInf), zero = _mm512_setzero_pd();
    const __m512d pxv = _mm512_set1_pd(px), pyv = _mm512_set1_pd(py);
    bool wall_ok = false, wall_x = true;
    const WallLight* wl = nullptr;
    int wall_mat = 0, d_begin = 0, d_end = 0;
    if (surf == Surf::kWall) {
      const WallSegment& ws = world.walls[id];
      wall_mat = ws.material;
      wall_x = ws.along_x;
      wl = &wall_light[id];
      d_begin = decal_begin[id], d_end = decal_end[id];
      wall_ok = mats[wall_mat].mirror <= 0;
      for (int i = d_begin; i < d_end; ++i) wall_ok = wall_ok && mats[decals[i].material].mirror <= 0;
    }
    static_assert(sizeof(Cell) == 16 && offsetof(Cell, floor_mat) == 4 && offsetof(Cell, ceil_mat) == 6 &&
                  offsetof(Cell, flat) == 8 && offsetof(Cell, light) == 12);
    const int* cell_words = reinterpret_cast<const int*>(cells.data());
    for (int i0 = 0; i0 < nn; i0 += 8) {
      const __m512d r = _mm512_loadu_pd(sr + i0);
      __mmask8 ok = _mm512_cmp_pd_mask(r, inf, _CMP_NEQ_UQ);
      const __m512d dx = _mm512_loadu_pd(sdx + i0), dy = _mm512_loadu_pd(sdy + i0);
      const __m512d x = _mm512_add_pd(pxv, _mm512_mul_pd(dx, r)), y = _mm512_add_pd(pyv, _mm512_mul_pd(dy, r));
      __m512d res = zero;
      if (surf == Surf::kFloor || surf == Surf::kCeiling) {
        // GridIndex and the cell's words
        const __m256i cw4 = GridWord8(x, y);
        const __m256 irr_f = _mm256_mmask_i32gather_ps(_mm256_setzero_ps(), ok, cw4, &cells[0].irr, 4);
        const __m256i mats_w = _mm256_mmask_i32gather_epi32(_mm256_setzero_si256(), ok, _mm256_add_epi32(cw4, _mm256_set1_epi32(1)), cell_words, 4);
        __m256i mat;
        __mmask8 panel = 0;  // (ceiling) on a light panel: its radiance
        __m512d panel_val = zero;
        if (surf == Surf::kFloor) {
          const __m256i flat = _mm256_srai_epi32(_mm256_slli_epi32(_mm256_mmask_i32gather_epi32(_mm256_setzero_si256(), ok, _mm256_add_epi32(cw4, _mm256_set1_epi32(2)), cell_words, 4), 16), 16);
          ok &= _mm256_cmpeq_epi32_mask(flat, _mm256_set1_epi32(-1));
          mat = _mm256_srai_epi32(_mm256_slli_epi32(mats_w, 16), 16);  // floor_mat (low half)
        } else {
          const __m256i light = _mm256_mmask_i32gather_epi32(_mm256_setzero_si256(), ok, _mm256_add_epi32(cw4, _mm256_set1_epi32(3)), cell_words, 4);
          const __mmask8 in_cell = ok & _mm256_cmpge_epi32_mask(light, _mm256_setzero_si256());
          if (in_cell) {  // Shade's panel test, lane by lane; a point of the cell off the panel is plain ceiling
            static_assert(sizeof(PanelFast) == 5 * sizeof(double));
            const __m256i li = _mm256_mullo_epi32(light, _mm256_set1_epi32(5));
            const double* pb = &panels[0].cx;
            const __m512d cx = _mm512_mask_i32gather_pd(zero, in_cell, li, pb, 8), cy = _mm512_mask_i32gather_pd(zero, in_cell, li, pb + 1, 8);
            const __m512d hx = _mm512_mask_i32gather_pd(zero, in_cell, li, pb + 2, 8), hy = _mm512_mask_i32gather_pd(zero, in_cell, li, pb + 3, 8);
            panel = in_cell & _mm512_cmp_pd_mask(_mm512_abs_pd(_mm512_sub_pd(x, cx)), hx, _CMP_LE_OQ) &
                    _mm512_cmp_pd_mask(_mm512_abs_pd(_mm512_sub_pd(y, cy)), hy, _CMP_LE_OQ);
            panel_val = _mm512_mask_i32gather_pd(zero, panel, li, pb + 4, 8);
          }
          ok &= static_cast<__mmask8>(~panel);
          mat = _mm256_srai_epi32(mats_w, 16);  // ceil_mat (high half)
        }
        if (ok) {
          __m512d texv, albedo, emission;
          TexMaterialSimd(mat, x, y, ok, texv, albedo, emission);
          const __m512d irr = _mm512_cvtps_pd(irr_f);
          const __m512d e = surf == Surf::kFloor ? irr : _mm512_add_pd(_mm512_set1_pd(world.ambient), _mm512_mul_pd(_mm512_set1_pd(kCeilingBounce), irr));
          res = _mm512_add_pd(_mm512_mul_pd(_mm512_mul_pd(albedo, texv), e), emission);
        }
        res = _mm512_mask_blend_pd(panel, res, panel_val);
        ok |= panel;
      } else if (surf == Surf::kWall && wall_ok) {
        const __m512d k = _mm512_cvtps_pd(_mm256_loadu_ps(soa + 2 * nn + i0));
        const __m512d along = wall_x ? x : y;
        const __m512d z = _mm512_add_pd(_mm512_set1_pd(cam_h), _mm512_mul_pd(k, r));
        __m256i mat = _mm256_set1_epi32(wall_mat);
        __m512d tu = along, tv = z;
        __mmask8 free = 0xFF;
        for (int d = d_begin; d < d_end && free; ++d) {
          const Decal& dc = decals[d];
          const __mmask8 in = free & _mm512_cmp_pd_mask(along, _mm512_set1_pd(dc.lo), _CMP_GE_OQ) &
                              _mm512_cmp_pd_mask(along, _mm512_set1_pd(dc.hi), _CMP_LE_OQ) &
                              _mm512_cmp_pd_mask(z, _mm512_set1_pd(dc.z0), _CMP_GE_OQ) & _mm512_cmp_pd_mask(z, _mm512_set1_pd(dc.z1), _CMP_LE_OQ);
          mat = _mm256_mask_blend_epi32(in, mat, _mm256_set1_epi32(dc.material));
          tu = _mm512_mask_blend_pd(in, tu, _mm512_sub_pd(along, _mm512_set1_pd(dc.lo)));
          tv = _mm512_mask_blend_pd(in, tv, _mm512_sub_pd(_mm512_set1_pd(dc.z1), z));
          free &= static_cast<__mmask8>(~in);
        }
        const __m512d e = WallIrradiance8(*wl, along, z, ok);
        __m512d texv, albedo, emission;
        TexMaterialSimd(mat, tu, tv, ok, texv, albedo, emission);
        res = _mm512_add_pd(_mm512_mul_pd(_mm512_mul_pd(albedo, texv), e), _mm512_mul_pd(emission, texv));
      } else {
        ok = 0;
      }
      _mm512_storeu_pd(val + i0, res);
      for (int k = 0; k < 8; ++k) done[i0 + k] = ok >> k & 1;
    }
  }
#endif

#ifdef SQUINT_RENDER_SIMD
  // --- AVX2 (CPUs without AVX-512): the functions above four samples per step, no FMA --------
  // A mask is a vector of all-ones (true) or zero lanes: __m256d over four doubles, __m128i over
  // four ints. Most table reads are plain loads per lane, or one broadcast where the four lanes
  // read the same entry (walls, materials), rather than gathers (on the AMD Zen 3 development
  // machine the gathers made this path no faster than the scalar code); a lane whose index may
  // be invalid (masked out) reads entry 0 instead, and its result is not used.
  // Four double lanes' mask as four int lanes.
  [[gnu::target("avx2"), gnu::always_inline]] static inline __m128i Mask32(__m256d m) {
    const __m128 lo = _mm256_castps256_ps128(_mm256_castpd_ps(m)), hi = _mm256_extractf128_ps(_mm256_castpd_ps(m), 1);
    return _mm_castps_si128(_mm_shuffle_ps(lo, hi, _MM_SHUFFLE(2, 0, 2, 0)));
  }
  // Four int lanes' mask as four double lanes.
  [[gnu::target("avx2"), gnu::always_inline]] static inline __m256d Mask64(__m128i m) {
    return _mm256_castsi256_pd(_mm256_cvtepi32_epi64(m));
  }
  [[gnu::target("avx2"), gnu::always_inline]] static inline int Bits32(__m128i m) { return _mm_movemask_ps(_mm_castsi128_ps(m)); }
  // Whether the four int lanes are equal.
  [[gnu::target("avx2"), gnu::always_inline]] static inline bool Uniform(__m128i x) {
    return Bits32(_mm_cmpeq_epi32(x, _mm_shuffle_epi32(x, 0))) == 0xF;
  }
  // base[idx] per lane.
  [[gnu::target("avx2"), gnu::always_inline]] static inline __m128 LoadF4(const float* base, __m128i idx) {
    alignas(16) int i[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(i), idx);
    return _mm_setr_ps(base[i[0]], base[i[1]], base[i[2]], base[i[3]]);
  }
  // base[idx] and base[idx + 1] per lane.
  [[gnu::target("avx2"), gnu::always_inline]] static inline void LoadPairs4(const float* base, __m128i idx, __m128& c0, __m128& c1) {
    alignas(16) int i[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(i), idx);
    const __m128 p01 = _mm_loadh_pi(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(base + i[0]))),
                                    reinterpret_cast<const __m64*>(base + i[1]));
    const __m128 p23 = _mm_loadh_pi(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(base + i[2]))),
                                    reinterpret_cast<const __m64*>(base + i[3]));
    c0 = _mm_shuffle_ps(p01, p23, _MM_SHUFFLE(2, 0, 2, 0));
    c1 = _mm_shuffle_ps(p01, p23, _MM_SHUFFLE(3, 1, 3, 1));
  }
  // Four rows of four doubles as columns.
  [[gnu::target("avx2"), gnu::always_inline]] static inline void Transpose4(__m256d& a0, __m256d& a1, __m256d& a2, __m256d& a3) {
    const __m256d t0 = _mm256_unpacklo_pd(a0, a1), t1 = _mm256_unpackhi_pd(a0, a1);
    const __m256d t2 = _mm256_unpacklo_pd(a2, a3), t3 = _mm256_unpackhi_pd(a2, a3);
    a0 = _mm256_permute2f128_pd(t0, t2, 0x20), a1 = _mm256_permute2f128_pd(t1, t3, 0x20);
    a2 = _mm256_permute2f128_pd(t0, t2, 0x31), a3 = _mm256_permute2f128_pd(t1, t3, 0x31);
  }
  [[gnu::target("avx2"), gnu::always_inline]] static inline double HMin4(__m256d v) {
    const __m128d m = _mm_min_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
    return _mm_cvtsd_f64(_mm_min_sd(m, _mm_unpackhi_pd(m, m)));
  }
  [[gnu::target("avx2"), gnu::always_inline]] static inline double HMax4(__m256d v) {
    const __m128d m = _mm_max_pd(_mm256_castpd256_pd128(v), _mm256_extractf128_pd(v, 1));
    return _mm_cvtsd_f64(_mm_max_sd(m, _mm_unpackhi_pd(m, m)));
  }

  // WallDistance for four directions from a wall's fields (each lane its wall's), lane by lane.
  [[gnu::target("avx2"), gnu::always_inline]] static inline __m256d WallDistance4(__m256d off, __m256d sx, __m256d sy, __m256d base,
                                                                                 __m256d lo, __m256d hi, __m256d dx, __m256d dy) {
    const __m256d t = _mm256_div_pd(off, _mm256_add_pd(_mm256_mul_pd(sx, dx), _mm256_mul_pd(sy, dy)));
    const __m256d along = _mm256_add_pd(base, _mm256_mul_pd(t, _mm256_add_pd(_mm256_mul_pd(sy, dx), _mm256_mul_pd(sx, dy))));
    const __m256d ok = _mm256_and_pd(_mm256_cmp_pd(t, _mm256_setzero_pd(), _CMP_GT_OQ),
                                     _mm256_and_pd(_mm256_cmp_pd(along, lo, _CMP_GE_OQ), _mm256_cmp_pd(along, hi, _CMP_LE_OQ)));
    return _mm256_blendv_pd(_mm256_set1_pd(kInf), t, ok);
  }
  // ... for four walls (w, -1 for none): each wall's record (lo, hi, coord, off, then base, sx,
  // sy) loaded as two rows and transposed.
  [[gnu::target("avx2"), gnu::always_inline]] inline __m256d WallDistance4(__m128i w, __m256d dx, __m256d dy) const {
    if (Uniform(w)) return WallDistance4(_mm_cvtsi128_si32(w), dx, dy);
    static_assert(offsetof(WallFast, lo) == 0 && offsetof(WallFast, hi) == 8 && offsetof(WallFast, coord) == 16 &&
                  offsetof(WallFast, off) == 24 && offsetof(WallFast, base) == 32 && offsetof(WallFast, sx) == 40 &&
                  offsetof(WallFast, sy) == 48 && sizeof(WallFast) >= 64);
    alignas(16) int i[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(i), w);
    const double* f[4] = {&wf[i[0]].lo, &wf[i[1]].lo, &wf[i[2]].lo, &wf[i[3]].lo};
    __m256d lo = _mm256_loadu_pd(f[0]), hi = _mm256_loadu_pd(f[1]), coord = _mm256_loadu_pd(f[2]), off = _mm256_loadu_pd(f[3]);
    __m256d base = _mm256_loadu_pd(f[0] + 4), sx = _mm256_loadu_pd(f[1] + 4), sy = _mm256_loadu_pd(f[2] + 4), rest = _mm256_loadu_pd(f[3] + 4);
    Transpose4(lo, hi, coord, off);
    Transpose4(base, sx, sy, rest);
    return WallDistance4(off, sx, sy, base, lo, hi, dx, dy);
  }
  // ... for one wall w.
  [[gnu::target("avx2"), gnu::always_inline]] inline __m256d WallDistance4(int w, __m256d dx, __m256d dy) const {
    const WallFast& f = wf[w];
    return WallDistance4(_mm256_set1_pd(f.off), _mm256_set1_pd(f.sx), _mm256_set1_pd(f.sy), _mm256_set1_pd(f.base),
                         _mm256_set1_pd(f.lo), _mm256_set1_pd(f.hi), dx, dy);
  }

  // GridIndex for four floor points, in floats from the start of `cells` (the cell's words).
  [[gnu::target("avx2"), gnu::always_inline]] inline __m128i GridWord4(__m256d x, __m256d y) const {
    constexpr int kCellStride = sizeof(Cell) / sizeof(float);
    __m128i gi = _mm256_cvttpd_epi32(_mm256_mul_pd(_mm256_sub_pd(x, _mm256_set1_pd(gx0)), _mm256_set1_pd(1.0 / kCell)));
    __m128i gj = _mm256_cvttpd_epi32(_mm256_mul_pd(_mm256_sub_pd(y, _mm256_set1_pd(gy0)), _mm256_set1_pd(1.0 / kCell)));
    gi = _mm_min_epi32(_mm_max_epi32(gi, _mm_setzero_si128()), _mm_set1_epi32(gnx - 1));
    gj = _mm_min_epi32(_mm_max_epi32(gj, _mm_setzero_si128()), _mm_set1_epi32(gny - 1));
    return _mm_mullo_epi32(_mm_add_epi32(_mm_mullo_epi32(gj, _mm_set1_epi32(gnx)), gi), _mm_set1_epi32(kCellStride));
  }

  // WallIrradiance for four points (along, z) of the wall lit by `wl` (lanes outside m read nothing).
  [[gnu::target("avx2"), gnu::always_inline]] inline __m256d WallIrradiance4(const WallLight& wl, __m256d along, __m256d z, __m256d m) const {
    const __m256d zero = _mm256_setzero_pd(), wall_s = _mm256_set1_pd(1.0 / kWallCell), fmax = _mm256_set1_pd(wl.fu_max);
    __m256d fu = _mm256_mul_pd(_mm256_sub_pd(along, _mm256_set1_pd(wl.lo)), wall_s);
    fu = _mm256_blendv_pd(fu, zero, _mm256_cmp_pd(fu, zero, _CMP_LT_OQ));
    fu = _mm256_blendv_pd(fu, fmax, _mm256_cmp_pd(fmax, fu, _CMP_LT_OQ));
    const __m128i iu = _mm256_cvttpd_epi32(fu);
    __m128i iz = _mm256_cvttpd_epi32(_mm256_add_pd(_mm256_mul_pd(z, wall_s), _mm256_set1_pd(0.5)));
    iz = _mm_min_epi32(_mm_max_epi32(iz, _mm_setzero_si128()), _mm_set1_epi32(wl.nz - 1));
    const __m128i cell = _mm_and_si128(_mm_add_epi32(_mm_mullo_epi32(iz, _mm_set1_epi32(wl.nu)), iu), Mask32(m));
    __m128 c0, c1;
    LoadPairs4(wl.irr, cell, c0, c1);
    return _mm256_add_pd(_mm256_cvtps_pd(c0), _mm256_mul_pd(_mm256_sub_pd(fu, _mm256_cvtepi32_pd(iu)), _mm256_cvtps_pd(_mm_sub_ps(c1, c0))));
  }

  // CornerWallsSimd, four corners per AVX2 step.
  [[gnu::target("avx2")]] std::size_t CornerWallsAvx2() {
    const std::size_t nc = corners.size();
    const __m256d cy = _mm256_set1_pd(cyaw), sy = _mm256_set1_pd(syaw);
    std::size_t i = 0;
    for (; i + 4 <= nc; i += 4) {
      const __m256d ca = _mm256_cvtps_pd(_mm_loadu_ps(&corner_ca[i])), sa = _mm256_cvtps_pd(_mm_loadu_ps(&corner_sa[i]));
      const __m256d dx = _mm256_sub_pd(_mm256_mul_pd(cy, ca), _mm256_mul_pd(sy, sa));
      const __m256d dy = _mm256_add_pd(_mm256_mul_pd(sy, ca), _mm256_mul_pd(cy, sa));
      const int* b = &corner_bin[i];
      const __m128i w0 = _mm_setr_epi32(edge_wall[b[0]], edge_wall[b[1]], edge_wall[b[2]], edge_wall[b[3]]);
      const __m128i w1 = _mm_setr_epi32(edge_wall[b[0] + 1], edge_wall[b[1] + 1], edge_wall[b[2] + 1], edge_wall[b[3] + 1]);
      const __m128i same = _mm_cmpeq_epi32(w0, w1);
      const __m256d t0 = WallDistance4(w0, dx, dy);
      const __m256d t1 = Bits32(same) == 0xF ? t0 : WallDistance4(w1, dx, dy);
      const __m256d first = _mm256_or_pd(Mask64(same), _mm256_cmp_pd(t0, t1, _CMP_LE_OQ));  // (w1 == w0: w0 and t0)
      _mm256_storeu_pd(&corner_dx[i], dx);
      _mm256_storeu_pd(&corner_dy[i], dy);
      _mm256_storeu_pd(&corner_r[i], _mm256_blendv_pd(t1, t0, first));
      _mm_storeu_si128(reinterpret_cast<__m128i*>(&corner_id[i]), _mm_blendv_epi8(w1, w0, Mask32(first)));
    }
    return i;
  }

  // WallEdgesSimd, four edges per AVX2 step.
  [[gnu::target("avx2")]] int WallEdgesAvx2(int w, int e0, int e1, const double* across, const double* other, double num, double base,
                                            double lo_e, double hi_e) {
    const __m256d abs_mask = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7FFFFFFFFFFFFFFFll));
    int e = e0;
    for (; e + 3 <= e1; e += 4) {
      const __m256d a = _mm256_loadu_pd(across + e), et = _mm256_loadu_pd(&edge_t[e]);
      const __m256d t = _mm256_div_pd(_mm256_set1_pd(num), a);
      const __m256d along = _mm256_add_pd(_mm256_set1_pd(base), _mm256_mul_pd(t, _mm256_loadu_pd(other + e)));
      const __m256d take = _mm256_and_pd(
          _mm256_and_pd(_mm256_cmp_pd(_mm256_and_pd(a, abs_mask), _mm256_set1_pd(1e-12), _CMP_NLT_UQ), _mm256_cmp_pd(t, _mm256_setzero_pd(), _CMP_NLE_UQ)),
          _mm256_and_pd(_mm256_cmp_pd(t, et, _CMP_NGE_UQ),
                        _mm256_and_pd(_mm256_cmp_pd(along, _mm256_set1_pd(lo_e), _CMP_NLT_UQ), _mm256_cmp_pd(along, _mm256_set1_pd(hi_e), _CMP_NGT_UQ))));
      _mm256_maskstore_pd(&edge_t[e], _mm256_castpd_si256(take), t);
      _mm_maskstore_epi32(&edge_wall[e], Mask32(take), _mm_set1_epi32(w));
    }
    return e;
  }

  // ColumnBoundsSimd, four bins per AVX2 step.
  [[gnu::target("avx2")]] void ColumnBoundsAvx2(int u, double& t, double& near, bool& any_obstacle) const {
    const int lo = col_bin_lo[u], hi = col_bin_hi[u];
    const __m128i lane = _mm_setr_epi32(0, 1, 2, 3);
    const __m256d inf = _mm256_set1_pd(kInf);
    __m256d tv = _mm256_setzero_pd(), nv = inf;
    __m128i listed = _mm_setzero_si128();
    for (int e = lo; e <= hi + 1; e += 4) {
      const __m128i me = _mm_cmpgt_epi32(_mm_set1_epi32(hi + 2 - e), lane), mb = _mm_cmpgt_epi32(_mm_set1_epi32(hi + 1 - e), lane);
      tv = _mm256_max_pd(tv, _mm256_maskload_pd(&edge_t[e], _mm256_cvtepi32_epi64(me)));  // (a lane left out reads 0)
      nv = _mm256_min_pd(nv, _mm256_blendv_pd(inf, _mm256_maskload_pd(&bin_near[e], _mm256_cvtepi32_epi64(mb)), Mask64(mb)));
      listed = _mm_or_si128(listed, _mm_cmpgt_epi32(_mm_maskload_epi32(&bin_count[e], mb), _mm_setzero_si128()));
    }
    t = HMax4(tv);
    near = HMin4(nv);
    any_obstacle = Bits32(listed) != 0;
  }

  // MarkRowsSimd, four rows per AVX2 step.
  [[gnu::target("avx2")]] int MarkRowsAvx2(double ua, double ub, double va, double dv, int u0, int u1, int v0, int v1, std::uint8_t bit) {
    constexpr double kPad = 1e-3;
    const __m256d zero = _mm256_setzero_pd(), one = _mm256_set1_pd(1.0);
    const __m256d vav = _mm256_set1_pd(va), dvv = _mm256_set1_pd(dv), uav = _mm256_set1_pd(ua), dua = _mm256_set1_pd(ub - ua);
    int v = v0;
    for (; v + 3 <= v1; v += 4) {
      const __m256d vd = _mm256_cvtepi32_pd(_mm_add_epi32(_mm_set1_epi32(v), _mm_setr_epi32(0, 1, 2, 3)));
      const __m256d r0 = _mm256_div_pd(_mm256_sub_pd(_mm256_sub_pd(_mm256_sub_pd(vd, _mm256_set1_pd(0.5)), _mm256_set1_pd(kPad)), vav), dvv);
      const __m256d r1 = _mm256_div_pd(_mm256_sub_pd(_mm256_add_pd(_mm256_add_pd(vd, _mm256_set1_pd(0.5)), _mm256_set1_pd(kPad)), vav), dvv);
      // std::clamp(r, 0.0, 1.0): r < 0 ? 0 : (1 < r ? 1 : r)
      const __m256d t0 = _mm256_blendv_pd(_mm256_blendv_pd(r0, one, _mm256_cmp_pd(one, r0, _CMP_LT_OQ)), zero, _mm256_cmp_pd(r0, zero, _CMP_LT_OQ));
      const __m256d t1 = _mm256_blendv_pd(_mm256_blendv_pd(r1, one, _mm256_cmp_pd(one, r1, _CMP_LT_OQ)), zero, _mm256_cmp_pd(r1, zero, _CMP_LT_OQ));
      const __m256d x0 = _mm256_add_pd(uav, _mm256_mul_pd(t0, dua)), x1 = _mm256_add_pd(uav, _mm256_mul_pd(t1, dua));
      const __m256d swap = _mm256_cmp_pd(x1, x0, _CMP_LT_OQ);  // std::min(x0, x1) is x1 there, std::max x0
      const __m256d lo = _mm256_blendv_pd(x0, x1, swap), hi = _mm256_blendv_pd(x1, x0, swap);
      const __m256d cl = _mm256_round_pd(_mm256_sub_pd(_mm256_sub_pd(lo, _mm256_set1_pd(0.5)), _mm256_set1_pd(kPad)), _MM_FROUND_TO_POS_INF | _MM_FROUND_NO_EXC);
      const __m256d fh = _mm256_round_pd(_mm256_add_pd(_mm256_add_pd(hi, _mm256_set1_pd(0.5)), _mm256_set1_pd(kPad)), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC);
      alignas(16) int c0[4], c1[4];
      _mm_store_si128(reinterpret_cast<__m128i*>(c0), _mm_max_epi32(_mm_set1_epi32(u0), _mm256_cvttpd_epi32(cl)));
      _mm_store_si128(reinterpret_cast<__m128i*>(c1), _mm_min_epi32(_mm_set1_epi32(u1), _mm256_cvttpd_epi32(fh)));
      for (int k = 0; k < 4; ++k)
        for (int u = c0[k]; u <= c1[k]; ++u) mask[static_cast<std::size_t>(v + k) * camera.width + u] |= bit;
    }
    return v;
  }

  // PlanesSimd, four samples per AVX2 step.
  [[gnu::target("avx2")]] bool PlanesAvx2(std::size_t pixel, bool by_bins, int np, const std::uint32_t* keys, const std::uint32_t* kq,
                                          const bool* pq, double* sdx, double* sdy, double* sr, int* sid, Surf* ss, int* sq,
                                          int* count, PlainAccum* acc) const {
    const int nn = n * n;
    const float* soa = &sample_soa[pixel * nn * 4];
    const std::int32_t* bins_p = &sample_bin[pixel * nn];
    const __m256d cy = _mm256_set1_pd(cyaw), sy = _mm256_set1_pd(syaw), inf = _mm256_set1_pd(kInf), zero = _mm256_setzero_pd();
    const __m256d ceil_rel = _mm256_set1_pd(frame_ceiling - cam_h);
    const __m128i wall_surf = _mm_set1_epi32(static_cast<int>(Surf::kWall));
    const __m128i floor_key = _mm_set1_epi32(static_cast<int>(static_cast<std::uint32_t>(Surf::kFloor) << 24 | 0xFFFFFFu));
    const __m128i ceil_key = _mm_set1_epi32(static_cast<int>(static_cast<std::uint32_t>(Surf::kCeiling) << 24 | 0xFFFFFFu));
    for (int i0 = 0; i0 < nn; i0 += 4) {
      const __m256d ca = _mm256_cvtps_pd(_mm_loadu_ps(soa + i0)), sa = _mm256_cvtps_pd(_mm_loadu_ps(soa + nn + i0));
      const __m256d k = _mm256_cvtps_pd(_mm_loadu_ps(soa + 2 * nn + i0)), rk = _mm256_cvtps_pd(_mm_loadu_ps(soa + 3 * nn + i0));
      const __m256d dx = _mm256_sub_pd(_mm256_mul_pd(cy, ca), _mm256_mul_pd(sy, sa));
      const __m256d dy = _mm256_add_pd(_mm256_mul_pd(sy, ca), _mm256_mul_pd(cy, sa));
      _mm256_storeu_pd(sdx + i0, dx);
      _mm256_storeu_pd(sdy + i0, dy);
      __m256d r;
      __m128i id, key, surf, traced = _mm_setzero_si128();  // (by_bins) a sliver wall inside the bin: trace the sample
      if (by_bins) {
        // edge_wall[bin] and edge_wall[bin + 1] per lane
        __m128 p01 = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&edge_wall[bins_p[i0]])));
        __m128 p23 = _mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(&edge_wall[bins_p[i0 + 2]])));
        p01 = _mm_loadh_pi(p01, reinterpret_cast<const __m64*>(&edge_wall[bins_p[i0 + 1]]));
        p23 = _mm_loadh_pi(p23, reinterpret_cast<const __m64*>(&edge_wall[bins_p[i0 + 3]]));
        const __m128i w0 = _mm_castps_si128(_mm_shuffle_ps(p01, p23, _MM_SHUFFLE(2, 0, 2, 0)));
        const __m128i w1 = _mm_castps_si128(_mm_shuffle_ps(p01, p23, _MM_SHUFFLE(3, 1, 3, 1)));
        // w1 == w0 gives t1 == t0 bit for bit: the selection then keeps w0 and t0, as the scalar code does.
        const __m256d t0 = WallDistance4(w0, dx, dy);
        const __m256d t1 = Bits32(_mm_cmpeq_epi32(w0, w1)) == 0xF ? t0 : WallDistance4(w1, dx, dy);
        const __m256d first = _mm256_cmp_pd(t0, t1, _CMP_LE_OQ);
        id = _mm_blendv_epi8(w1, w0, Mask32(first));
        r = _mm256_blendv_pd(t1, t0, first);
        traced = Mask32(_mm256_cmp_pd(r, inf, _CMP_EQ_OQ));
        const __m256d rc = _mm256_mul_pd(ceil_rel, rk);
        const __m256d fl = _mm256_and_pd(_mm256_cmp_pd(k, zero, _CMP_LT_OQ), _mm256_cmp_pd(rk, r, _CMP_LT_OQ));
        const __m256d ce = _mm256_andnot_pd(fl, _mm256_and_pd(_mm256_cmp_pd(k, zero, _CMP_GT_OQ), _mm256_cmp_pd(rc, r, _CMP_LT_OQ)));
        r = _mm256_blendv_pd(r, rk, fl);
        r = _mm256_blendv_pd(r, rc, ce);
        const __m128i fl32 = Mask32(fl), ce32 = Mask32(ce);
        surf = _mm_blendv_epi8(wall_surf, _mm_set1_epi32(static_cast<int>(Surf::kFloor)), fl32);
        surf = _mm_blendv_epi8(surf, _mm_set1_epi32(static_cast<int>(Surf::kCeiling)), ce32);
        key = _mm_or_si128(_mm_slli_epi32(wall_surf, 24), id);
        key = _mm_blendv_epi8(key, floor_key, fl32);
        key = _mm_blendv_epi8(key, ceil_key, ce32);
      } else {
        r = inf;
        key = _mm_setzero_si128();
        for (int q = 0; q < np; ++q) {
          __m256d rq;
          switch (static_cast<Surf>(keys[q] >> 24)) {
            case Surf::kFloor: rq = _mm256_blendv_pd(inf, rk, _mm256_cmp_pd(k, zero, _CMP_LT_OQ)); break;
            case Surf::kCeiling: rq = _mm256_blendv_pd(inf, _mm256_mul_pd(ceil_rel, rk), _mm256_cmp_pd(k, zero, _CMP_GT_OQ)); break;
            case Surf::kWall: rq = WallDistance4(static_cast<int>(keys[q] & 0xFFFFFFu), dx, dy); break;
            default: rq = inf; break;
          }
          const __m256d nearer = _mm256_cmp_pd(rq, r, _CMP_LT_OQ);
          r = _mm256_blendv_pd(r, rq, nearer);
          key = _mm_blendv_epi8(key, _mm_set1_epi32(static_cast<int>(keys[q])), Mask32(nearer));
        }
        if (_mm256_movemask_pd(_mm256_cmp_pd(r, inf, _CMP_EQ_OQ))) return false;
        surf = _mm_srli_epi32(key, 24);
        id = _mm_blendv_epi8(_mm_set1_epi32(-1), _mm_and_si128(key, _mm_set1_epi32(0xFFFFFF)), _mm_cmpeq_epi32(surf, wall_surf));
      }
      if (!uniform_ceiling && Bits32(_mm_andnot_si128(traced, _mm_cmpeq_epi32(surf, _mm_set1_epi32(static_cast<int>(Surf::kCeiling))))))
        return false;
      __m128i q = _mm_set1_epi32(4);
      for (int c = 3; c >= 0; --c) q = _mm_blendv_epi8(q, _mm_set1_epi32(c), _mm_cmpeq_epi32(key, _mm_set1_epi32(static_cast<int>(kq[c]))));
      for (int c = 0; c < 4; ++c)
        if (!pq[c]) q = _mm_blendv_epi8(q, _mm_set1_epi32(4), _mm_cmpeq_epi32(q, _mm_set1_epi32(c)));
      q = _mm_or_si128(q, traced);  // -1
      _mm256_storeu_pd(sr + i0, r);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(sid + i0), id);
      _mm_storeu_si128(reinterpret_cast<__m128i*>(sq + i0), q);
      static_assert(sizeof(Surf) == 1);
      const int surf_bytes = _mm_cvtsi128_si32(_mm_shuffle_epi8(surf, _mm_setr_epi8(0, 4, 8, 12, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1)));
      std::memcpy(ss + i0, &surf_bytes, 4);
      for (int c = 0; c < 5; ++c) count[c] += __builtin_popcount(Bits32(_mm_cmpeq_epi32(q, _mm_set1_epi32(c))));
      count[4] += __builtin_popcount(Bits32(traced));
    }
    // Each plain plane's samples: light-map values lane by lane, summed in sample order.
    double e[kMaxSamples];
    const __m256d pxv = _mm256_set1_pd(px), pyv = _mm256_set1_pd(py), ninf = _mm256_set1_pd(-kInf);
    for (int qq = 0; qq < np; ++qq) {
      if (count[qq] == 0) continue;
      PlainAccum& a = acc[qq];
      const auto psurf = static_cast<Surf>(keys[qq] >> 24);
      __m256d u_lo = inf, u_hi = ninf, v_lo = inf, v_hi = ninf;
      for (int i0 = 0; i0 < nn; i0 += 4) {
        const __m128i m32 = _mm_cmpeq_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(sq + i0)), _mm_set1_epi32(qq));
        if (!Bits32(m32)) continue;
        const __m256d m = Mask64(m32);
        const __m256d r = _mm256_loadu_pd(sr + i0);
        const __m256d x = _mm256_add_pd(pxv, _mm256_mul_pd(_mm256_loadu_pd(sdx + i0), r));
        const __m256d y = _mm256_add_pd(pyv, _mm256_mul_pd(_mm256_loadu_pd(sdy + i0), r));
        __m256d ev, tu, tv;
        if (psurf == Surf::kWall) {
          const int wid = static_cast<int>(keys[qq] & 0xFFFFFFu);
          const __m256d k = _mm256_cvtps_pd(_mm_loadu_ps(soa + 2 * nn + i0));
          const __m256d z = _mm256_add_pd(_mm256_set1_pd(cam_h), _mm256_mul_pd(k, r));
          tu = wf[wid].along_x ? x : y;
          tv = z;
          ev = WallIrradiance4(wall_light[wid], tu, z, m);
        } else {
          tu = x;
          tv = y;
          const __m128i gidx = GridWord4(x, y);
          const __m256d irr = _mm256_cvtps_pd(LoadF4(&cells[0].irr, gidx));  // (every lane's index is in the grid)
          ev = psurf == Surf::kCeiling ? _mm256_add_pd(_mm256_set1_pd(world.ambient), _mm256_mul_pd(_mm256_set1_pd(kCeilingBounce), irr)) : irr;
        }
        _mm256_storeu_pd(e + i0, ev);
        // (min(tu, lo) is std::min(lo, tu): lo unless tu < lo)
        u_lo = _mm256_blendv_pd(u_lo, _mm256_min_pd(tu, u_lo), m), u_hi = _mm256_blendv_pd(u_hi, _mm256_max_pd(tu, u_hi), m);
        v_lo = _mm256_blendv_pd(v_lo, _mm256_min_pd(tv, v_lo), m), v_hi = _mm256_blendv_pd(v_hi, _mm256_max_pd(tv, v_hi), m);
      }
      double e_sum = 0;
      for (int i = 0; i < nn; ++i)
        if (sq[i] == qq) e_sum += e[i];
      a.e_sum = e_sum;
      a.u_lo = HMin4(u_lo), a.u_hi = HMax4(u_hi), a.v_lo = HMin4(v_lo), a.v_hi = HMax4(v_hi);
      a.count = count[qq];
    }
    return true;
  }

  // SplitSimd, four samples per AVX2 step.
  [[gnu::target("avx2")]] int SplitAvx2(const double* g, const double* gx, const double* gy, const double* gz, double h_rel, int w,
                                        bool along_x, double& pu_lo, double& pu_hi, double& pv_lo, double& pv_hi, double& pe,
                                        double& wu_lo, double& wu_hi, double& wv_lo, double& wv_hi, double& we) const {
    const int nn = n * n;
    const WallSegment& ws = world.walls[w];
    const WallLight& wl = wall_light[w];
    const double wall_c = ws.coord, wall_p = along_x ? py : px, wall_a = along_x ? px : py;
    const __m256d zero = _mm256_setzero_pd(), inf = _mm256_set1_pd(kInf), ninf = _mm256_set1_pd(-kInf);
    const __m256d g0 = _mm256_set1_pd(g[0]), g20 = _mm256_set1_pd(g[2] - g[0]), g1 = _mm256_set1_pd(g[1]), g31 = _mm256_set1_pd(g[3] - g[1]);
    const __m256d x0 = _mm256_set1_pd(gx[0]), x20 = _mm256_set1_pd(gx[2] - gx[0]), x1 = _mm256_set1_pd(gx[1]), x31 = _mm256_set1_pd(gx[3] - gx[1]);
    const __m256d y0 = _mm256_set1_pd(gy[0]), y20 = _mm256_set1_pd(gy[2] - gy[0]), y1 = _mm256_set1_pd(gy[1]), y31 = _mm256_set1_pd(gy[3] - gy[1]);
    const __m256d z0 = _mm256_set1_pd(gz[0]), z20 = _mm256_set1_pd(gz[2] - gz[0]), z1 = _mm256_set1_pd(gz[1]), z31 = _mm256_set1_pd(gz[3] - gz[1]);
    const __m256d hv = _mm256_set1_pd(h_rel), pxv = _mm256_set1_pd(px), pyv = _mm256_set1_pd(py), camz = _mm256_set1_pd(cam_h);
    const __m256d wcp = _mm256_set1_pd(wall_c - wall_p), wav = _mm256_set1_pd(wall_a);
    __m256d pul = inf, puh = ninf, pvl = inf, pvh = ninf, wul = inf, wuh = ninf, wvl = inf, wvh = ninf;
    double pev[kMaxSamples], wev[kMaxSamples];
    int on_bits[kMaxSamples / 4];
    int on_plane = 0;
    for (int i0 = 0; i0 < nn; i0 += 4) {
      const __m256d fx = _mm256_loadu_pd(&split_fx[i0]), fy = _mm256_loadu_pd(&split_fy[i0]);
      // Per row (fy) the left and right ends, then along the row (fx), as the scalar loop steps.
      const __m256d g_l = _mm256_add_pd(g0, _mm256_mul_pd(fy, g20)), g_r = _mm256_add_pd(g1, _mm256_mul_pd(fy, g31));
      const __m256d x_l = _mm256_add_pd(x0, _mm256_mul_pd(fy, x20)), x_r = _mm256_add_pd(x1, _mm256_mul_pd(fy, x31));
      const __m256d y_l = _mm256_add_pd(y0, _mm256_mul_pd(fy, y20)), y_r = _mm256_add_pd(y1, _mm256_mul_pd(fy, y31));
      const __m256d z_l = _mm256_add_pd(z0, _mm256_mul_pd(fy, z20)), z_r = _mm256_add_pd(z1, _mm256_mul_pd(fy, z31));
      const __m256d sdx = _mm256_add_pd(x_l, _mm256_mul_pd(fx, _mm256_sub_pd(x_r, x_l)));
      const __m256d sdy = _mm256_add_pd(y_l, _mm256_mul_pd(fx, _mm256_sub_pd(y_r, y_l)));
      const __m256d sdz = _mm256_add_pd(z_l, _mm256_mul_pd(fx, _mm256_sub_pd(z_r, z_l)));
      const __m256d on = _mm256_cmp_pd(_mm256_add_pd(g_l, _mm256_mul_pd(fx, _mm256_sub_pd(g_r, g_l))), zero, _CMP_GT_OQ);
      const int on_m = _mm256_movemask_pd(on);
      on_bits[i0 / 4] = on_m;
      on_plane += __builtin_popcount(on_m);
      if (on_m) {  // the floor or ceiling plane
        const __m256d t = _mm256_div_pd(hv, sdz);
        const __m256d x = _mm256_add_pd(pxv, _mm256_mul_pd(t, sdx)), y = _mm256_add_pd(pyv, _mm256_mul_pd(t, sdy));
        pul = _mm256_blendv_pd(pul, _mm256_min_pd(x, pul), on), puh = _mm256_blendv_pd(puh, _mm256_max_pd(x, puh), on);
        pvl = _mm256_blendv_pd(pvl, _mm256_min_pd(y, pvl), on), pvh = _mm256_blendv_pd(pvh, _mm256_max_pd(y, pvh), on);
        const __m128i gidx = GridWord4(x, y);
        _mm256_storeu_pd(pev + i0, _mm256_cvtps_pd(LoadF4(&cells[0].irr, gidx)));  // (every lane's index is in the grid)
      }
      if (on_m != 0xF) {  // the wall
        const __m256d off = _mm256_xor_pd(on, _mm256_castsi256_pd(_mm256_set1_epi64x(-1)));
        const __m256d across = along_x ? sdy : sdx, other = along_x ? sdx : sdy;
        const __m256d t = _mm256_div_pd(wcp, across);
        const __m256d along = _mm256_add_pd(wav, _mm256_mul_pd(t, other)), z = _mm256_add_pd(camz, _mm256_mul_pd(t, sdz));
        wul = _mm256_blendv_pd(wul, _mm256_min_pd(along, wul), off), wuh = _mm256_blendv_pd(wuh, _mm256_max_pd(along, wuh), off);
        wvl = _mm256_blendv_pd(wvl, _mm256_min_pd(z, wvl), off), wvh = _mm256_blendv_pd(wvh, _mm256_max_pd(z, wvh), off);
        _mm256_storeu_pd(wev + i0, WallIrradiance4(wl, along, z, off));
      }
    }
    double pe_sum = 0, we_sum = 0;
    for (int i = 0; i < nn; ++i) {
      if (on_bits[i / 4] >> (i % 4) & 1) pe_sum += pev[i];
      else we_sum += wev[i];
    }
    pe = pe_sum, we = we_sum;
    pu_lo = HMin4(pul), pu_hi = HMax4(puh), pv_lo = HMin4(pvl), pv_hi = HMax4(pvh);
    wu_lo = HMin4(wul), wu_hi = HMax4(wuh), wv_lo = HMin4(wvl), wv_hi = HMax4(wvh);
    return on_plane;
  }

  // TexMaterialSimd for four samples, every lane's material valid (each lane is read): one
  // material's fields broadcast, or each lane's loaded.
  [[gnu::target("avx2"), gnu::always_inline]] inline void TexMaterialAvx2(__m128i mat, __m256d u, __m256d v, __m256d& texv, __m256d& albedo,
                                                                          __m256d& emission) const {
    static_assert(detail::kTexSize == 128);
    const __m256d big = _mm256_set1_pd(16777216.0);
    const __m128i m127 = _mm_set1_epi32(detail::kTexSize - 1);
    alignas(16) int m[4], ti[4];
    _mm_store_si128(reinterpret_cast<__m128i*>(m), mat);
    const bool one = Uniform(mat);
    const TexelsFast* t[4] = {&texels_fast[m[0]], &texels_fast[m[1]], &texels_fast[m[2]], &texels_fast[m[3]]};
    const __m256d inv = one ? _mm256_set1_pd(t[0]->inv_texel_m)
                            : _mm256_cvtps_pd(_mm_setr_ps(t[0]->inv_texel_m, t[1]->inv_texel_m, t[2]->inv_texel_m, t[3]->inv_texel_m));
    const __m128i iu = _mm_and_si128(_mm256_cvttpd_epi32(_mm256_add_pd(_mm256_mul_pd(u, inv), big)), m127);
    const __m128i iv = _mm_and_si128(_mm256_cvttpd_epi32(_mm256_add_pd(_mm256_mul_pd(v, inv), big)), m127);
    _mm_store_si128(reinterpret_cast<__m128i*>(ti), _mm_add_epi32(_mm_slli_epi32(iv, 7), iu));
    const __m128i texel = _mm_setr_epi32(t[0]->texels[ti[0]], t[1]->texels[ti[1]], t[2]->texels[ti[2]], t[3]->texels[ti[3]]);
    if (one) {
      texv = _mm256_cvtps_pd(_mm_mul_ps(_mm_cvtepi32_ps(texel), _mm_set1_ps(t[0]->gain)));
      albedo = _mm256_set1_pd(mats[m[0]].albedo);
      emission = _mm256_set1_pd(mats[m[0]].emission);
    } else {
      texv = _mm256_cvtps_pd(_mm_mul_ps(_mm_cvtepi32_ps(texel), _mm_setr_ps(t[0]->gain, t[1]->gain, t[2]->gain, t[3]->gain)));
      albedo = _mm256_setr_pd(mats[m[0]].albedo, mats[m[1]].albedo, mats[m[2]].albedo, mats[m[3]].albedo);
      emission = _mm256_setr_pd(mats[m[0]].emission, mats[m[1]].emission, mats[m[2]].emission, mats[m[3]].emission);
    }
  }

  // ShadeOnPlaneSimd, four samples per AVX2 step.
  [[gnu::target("avx2")]] void ShadeOnPlaneAvx2(std::size_t pixel, Surf surf, int id, double* sdx, double* sdy, double* sr,
                                                double* val, bool* done) const {
    const int nn = n * n;
    bool wall_ok = false, wall_x = true;
    const WallLight* wl = nullptr;
    int wall_mat = 0, d_begin = 0, d_end = 0;
    if (surf == Surf::kWall) {
      const WallSegment& ws = world.walls[id];
      wall_mat = ws.material;
      wall_x = ws.along_x;
      wl = &wall_light[id];
      d_begin = decal_begin[id], d_end = decal_end[id];
      wall_ok = mats[wall_mat].mirror <= 0;
      for (int i = d_begin; i < d_end; ++i) wall_ok = wall_ok && mats[decals[i].material].mirror <= 0;
    }
    if (surf != Surf::kFloor && surf != Surf::kCeiling && !wall_ok) {
      std::fill(done, done + nn, false);
      return;
    }
    const float* soa = &sample_soa[pixel * nn * 4];
    const __m256d inf = _mm256_set1_pd(kInf), zero = _mm256_setzero_pd();
    const __m256d pxv = _mm256_set1_pd(px), pyv = _mm256_set1_pd(py);
    const float* cell_f = reinterpret_cast<const float*>(cells.data());
    for (int i0 = 0; i0 < nn; i0 += 4) {
      const __m256d r = _mm256_loadu_pd(sr + i0);
      __m256d ok = _mm256_cmp_pd(r, inf, _CMP_NEQ_UQ);
      const __m256d dx = _mm256_loadu_pd(sdx + i0), dy = _mm256_loadu_pd(sdy + i0);
      const __m256d x = _mm256_add_pd(pxv, _mm256_mul_pd(dx, r)), y = _mm256_add_pd(pyv, _mm256_mul_pd(dy, r));
      __m256d res = zero;
      if (surf == Surf::kFloor || surf == Surf::kCeiling) {
        // GridIndex and the cell's four words per lane (every lane's index is in the grid),
        // transposed: irradiance, materials, flat item, light panel.
        alignas(16) int cw[4];
        _mm_store_si128(reinterpret_cast<__m128i*>(cw), GridWord4(x, y));
        __m128 irr_f = _mm_loadu_ps(cell_f + cw[0]), mats_f = _mm_loadu_ps(cell_f + cw[1]);
        __m128 flat_f = _mm_loadu_ps(cell_f + cw[2]), light_f = _mm_loadu_ps(cell_f + cw[3]);
        _MM_TRANSPOSE4_PS(irr_f, mats_f, flat_f, light_f);
        const __m128i mats_w = _mm_castps_si128(mats_f);
        __m128i ok32 = Mask32(ok);
        __m128i mat;
        __m256d panel = _mm256_setzero_pd(), panel_val = _mm256_setzero_pd();  // (ceiling) on a light panel: its radiance
        if (surf == Surf::kFloor) {
          const __m128i flat_w = _mm_castps_si128(flat_f);
          ok32 = _mm_and_si128(ok32, _mm_cmpeq_epi32(_mm_srai_epi32(_mm_slli_epi32(flat_w, 16), 16), _mm_set1_epi32(-1)));
          mat = _mm_srai_epi32(_mm_slli_epi32(mats_w, 16), 16);  // floor_mat (low half)
        } else {
          const __m128i light = _mm_castps_si128(light_f);
          const __m128i in_cell = _mm_andnot_si128(_mm_cmplt_epi32(light, _mm_setzero_si128()), ok32);
          if (Bits32(in_cell)) {  // Shade's panel test, lane by lane; a point of the cell off the panel is plain ceiling
            alignas(16) int li[4];
            _mm_store_si128(reinterpret_cast<__m128i*>(li), _mm_and_si128(light, in_cell));  // (lane 0's panel elsewhere)
            const PanelFast* q[4] = {&panels[li[0]], &panels[li[1]], &panels[li[2]], &panels[li[3]]};
            const __m256d cx = _mm256_setr_pd(q[0]->cx, q[1]->cx, q[2]->cx, q[3]->cx), cy = _mm256_setr_pd(q[0]->cy, q[1]->cy, q[2]->cy, q[3]->cy);
            const __m256d hx = _mm256_setr_pd(q[0]->hx, q[1]->hx, q[2]->hx, q[3]->hx), hy = _mm256_setr_pd(q[0]->hy, q[1]->hy, q[2]->hy, q[3]->hy);
            const __m256d abs_mask = _mm256_castsi256_pd(_mm256_set1_epi64x(0x7FFFFFFFFFFFFFFFll));
            panel = _mm256_and_pd(Mask64(in_cell), _mm256_and_pd(_mm256_cmp_pd(_mm256_and_pd(_mm256_sub_pd(x, cx), abs_mask), hx, _CMP_LE_OQ),
                                                                 _mm256_cmp_pd(_mm256_and_pd(_mm256_sub_pd(y, cy), abs_mask), hy, _CMP_LE_OQ)));
            panel_val = _mm256_setr_pd(q[0]->radiance, q[1]->radiance, q[2]->radiance, q[3]->radiance);
          }
          ok32 = _mm_andnot_si128(Mask32(panel), ok32);
          mat = _mm_srai_epi32(mats_w, 16);  // ceil_mat (high half)
        }
        ok = Mask64(ok32);
        if (Bits32(ok32)) {
          __m256d texv, albedo, emission;
          TexMaterialAvx2(mat, x, y, texv, albedo, emission);  // (every lane's cell material)
          const __m256d irr = _mm256_cvtps_pd(irr_f);
          const __m256d e = surf == Surf::kFloor ? irr : _mm256_add_pd(_mm256_set1_pd(world.ambient), _mm256_mul_pd(_mm256_set1_pd(kCeilingBounce), irr));
          res = _mm256_add_pd(_mm256_mul_pd(_mm256_mul_pd(albedo, texv), e), emission);
        }
        res = _mm256_blendv_pd(res, panel_val, panel);
        ok = _mm256_or_pd(ok, panel);
      } else {  // a wall that is no mirror
        const __m256d k = _mm256_cvtps_pd(_mm_loadu_ps(soa + 2 * nn + i0));
        const __m256d along = wall_x ? x : y;
        const __m256d z = _mm256_add_pd(_mm256_set1_pd(cam_h), _mm256_mul_pd(k, r));
        __m128i mat = _mm_set1_epi32(wall_mat);
        __m256d tu = along, tv = z;
        __m256d free = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
        for (int d = d_begin; d < d_end && _mm256_movemask_pd(free); ++d) {
          const Decal& dc = decals[d];
          const __m256d in = _mm256_and_pd(
              _mm256_and_pd(free, _mm256_and_pd(_mm256_cmp_pd(along, _mm256_set1_pd(dc.lo), _CMP_GE_OQ), _mm256_cmp_pd(along, _mm256_set1_pd(dc.hi), _CMP_LE_OQ))),
              _mm256_and_pd(_mm256_cmp_pd(z, _mm256_set1_pd(dc.z0), _CMP_GE_OQ), _mm256_cmp_pd(z, _mm256_set1_pd(dc.z1), _CMP_LE_OQ)));
          mat = _mm_blendv_epi8(mat, _mm_set1_epi32(dc.material), Mask32(in));
          tu = _mm256_blendv_pd(tu, _mm256_sub_pd(along, _mm256_set1_pd(dc.lo)), in);
          tv = _mm256_blendv_pd(tv, _mm256_sub_pd(_mm256_set1_pd(dc.z1), z), in);
          free = _mm256_andnot_pd(in, free);
        }
        const __m256d e = WallIrradiance4(*wl, along, z, ok);
        __m256d texv, albedo, emission;
        TexMaterialAvx2(mat, tu, tv, texv, albedo, emission);
        res = _mm256_add_pd(_mm256_mul_pd(_mm256_mul_pd(albedo, texv), e), _mm256_mul_pd(emission, texv));
      }
      _mm256_storeu_pd(val + i0, res);
      const int bits = _mm256_movemask_pd(ok);
      for (int k = 0; k < 4; ++k) done[i0 + k] = bits >> k & 1;
    }
  }
#endif

  // Mean radiance of a pixel whose corners see several planes and no obstacle can stand in it:
  // each sample takes the nearest of the corners' planes (no tracing). Where a wall edge lies
  // in the pixel, or a wall thinner than the pixel could hide between floor and ceiling
  // corners, each sample instead tests the walls of its own bearing-table entries as Trace
  // does (without the obstacle search).
  double PixelPlanes(const Sample* s, const std::size_t (&idx)[4], bool geometry, bool pattern) const {
    constexpr std::uint32_t kFloorKey = static_cast<std::uint32_t>(Surf::kFloor) << 24 | 0xFFFFFFu;
    constexpr std::uint32_t kCeilingKey = static_cast<std::uint32_t>(Surf::kCeiling) << 24 | 0xFFFFFFu;
    std::uint32_t keys[4];
    int first[4];  // a corner on each plane
    bool plain[4];  // the plane's corners see one plain region, and no pattern edge is near
    int np = 0;
    bool has_floor = false, has_ceiling = false;
    for (int c = 0; c < 4; ++c) {
      const SurfPt& p = corner_pt[idx[c]];
      const int q = static_cast<int>(std::find(keys, keys + np, p.key1) - keys);
      if (q == np) keys[np] = p.key1, first[np] = c, plain[np] = !pattern && p.mat >= 0 && (p.key2 & 0xFFFFu) == 0, ++np;
      plain[q] = plain[q] && p.key2 == corner_pt[idx[first[q]]].key2;
      has_floor = has_floor || p.key1 == kFloorKey;
      has_ceiling = has_ceiling || p.key1 == kCeilingKey;
    }
    if (np == 2 && !geometry && plain[0] && plain[1]) {
      const bool wall0 = static_cast<Surf>(keys[0] >> 24) == Surf::kWall, wall1 = static_cast<Surf>(keys[1] >> 24) == Surf::kWall;
      if (wall0 != wall1) {
        const double mean = PixelSplit(idx, wall0 ? keys[0] : keys[1], wall0 ? keys[1] : keys[0]);
        if (mean >= 0) return mean;
      }
    }
    PlainAccum acc[4];
    const bool by_bins = geometry || (has_floor && has_ceiling);
    const int nn = n * n;
    const int depth = has_mirrors ? 0 : 1;
    double sum = 0;
    const Sample* s0 = s;
    // The planes padded to four (a key no hit has), so that a lookup is four selects; pq[4]: none.
    std::uint32_t kq[4];
    bool pq[5];
    for (int q = 0; q < 4; ++q) kq[q] = q < np ? keys[q] : 0xFFFFFFFFu, pq[q] = q < np && plain[q];
    pq[4] = false;
    const double ceil_rel = frame_ceiling - cam_h;
    // First every sample's hit (plane, distance) and its plane's slot (4: shade it alone, -1:
    // trace it), then each plain plane's samples in a loop of its own, then the others in
    // sample order (the same sums in the same order as one pass over the samples).
    double sdx[kMaxSamples], sdy[kMaxSamples], sr[kMaxSamples];
    int sid[kMaxSamples], sq[kMaxSamples];
    Surf ss[kMaxSamples];
    int count[5] = {0, 0, 0, 0, 0};
#ifdef SQUINT_RENDER_SIMD
    if (simd) {
      const std::size_t pixel = static_cast<std::size_t>(s - samples.data()) / nn;
      if (!(avx512 ? PlanesSimd(pixel, by_bins, np, keys, kq, pq, sdx, sdy, sr, sid, ss, sq, count, acc)
                   : PlanesAvx2(pixel, by_bins, np, keys, kq, pq, sdx, sdy, sr, sid, ss, sq, count, acc)))
        return PixelTraced(s0);
      goto shade_rest;
    }
#endif
    for (int i = 0; i < nn; ++i, ++s) {
      const double dx = cyaw * s->ca - syaw * s->sa, dy = syaw * s->ca + cyaw * s->sa;
      sdx[i] = dx, sdy[i] = dy;
      double r;
      int id;
      Surf surf;
      if (by_bins) {
        const int w0 = edge_wall[s->bin], w1 = edge_wall[s->bin + 1];
        r = WallDistance(w0, dx, dy);
        id = w0;
        if (w1 != w0) {
          const double t1 = WallDistance(w1, dx, dy);
          id = r <= t1 ? w0 : w1;
          r = r <= t1 ? r : t1;
        }
        if (r == kInf) {  // a sliver wall inside the bin: trace this sample
          sq[i] = -1;
          ++count[4];
          continue;
        }
        surf = Surf::kWall;
        const double rc = ceil_rel * s->rk;
        if (s->k < 0 && s->rk < r) {
          surf = Surf::kFloor, r = s->rk;
        } else if (s->k > 0 && rc < r) {
          surf = Surf::kCeiling, r = rc;
        }
      } else {
        std::uint32_t best_key = 0;
        r = kInf;
        for (int q = 0; q < np; ++q) {
          const double rq = PlaneDistance(keys[q], *s, dx, dy);
          if (rq < r) r = rq, best_key = keys[q];
        }
        if (r == kInf) return PixelTraced(s0);
        surf = static_cast<Surf>(best_key >> 24);
        id = surf == Surf::kWall ? static_cast<int>(best_key & 0xFFFFFFu) : -1;
      }
      if (surf == Surf::kCeiling && !uniform_ceiling) return PixelTraced(s0);
      const std::uint32_t key = static_cast<std::uint32_t>(surf) << 24 | (surf == Surf::kWall ? static_cast<std::uint32_t>(id) : 0xFFFFFFu);
      int q = 4;
      q = kq[3] == key ? 3 : q;
      q = kq[2] == key ? 2 : q;
      q = kq[1] == key ? 1 : q;
      q = kq[0] == key ? 0 : q;
      q = pq[q] ? q : 4;
      sr[i] = r, sid[i] = id, ss[i] = surf, sq[i] = q;
      ++count[q];
    }
    s = s0;
    for (int q = 0; q < np; ++q) {  // (Accumulate, written out)
      if (count[q] == 0) continue;
      PlainAccum& a = acc[q];
      const auto surf = static_cast<Surf>(keys[q] >> 24);
      if (surf == Surf::kWall) {
        const int id = static_cast<int>(keys[q] & 0xFFFFFFu);
        const bool along_x = wf[id].along_x;
        for (int i = 0; i < nn; ++i) {
          if (sq[i] != q) continue;
          const double r = sr[i];
          const double x = px + sdx[i] * r, y = py + sdy[i] * r;
          const double z = cam_h + s[i].k * r;
          const double tu = along_x ? x : y;
          a.e_sum += WallIrradiance(id, tu, z);
          a.u_lo = std::min(a.u_lo, tu), a.u_hi = std::max(a.u_hi, tu);
          a.v_lo = std::min(a.v_lo, z), a.v_hi = std::max(a.v_hi, z);
        }
      } else {
        const bool ceiling = surf == Surf::kCeiling;
        for (int i = 0; i < nn; ++i) {
          if (sq[i] != q) continue;
          const double r = sr[i];
          const double x = px + sdx[i] * r, y = py + sdy[i] * r;
          const double irr = cells[GridIndex(x, y)].irr;
          a.e_sum += ceiling ? world.ambient + kCeilingBounce * irr : irr;
          a.u_lo = std::min(a.u_lo, x), a.u_hi = std::max(a.u_hi, x);
          a.v_lo = std::min(a.v_lo, y), a.v_hi = std::max(a.v_hi, y);
        }
      }
      a.count = count[q];
    }
#ifdef SQUINT_RENDER_SIMD
  shade_rest:
#endif
    if (count[4] > 0)
      for (int i = 0; i < nn; ++i) {
        if (sq[i] == 4) {
          Hit hit;
          hit.surf = ss[i], hit.id = sid[i], hit.r = sr[i];
          sum += Shade(hit, px, py, cam_h, sdx[i], sdy[i], s[i].k, depth);
        } else if (sq[i] < 0) {
          double tx, ty;
          sum += Shade(Trace(s[i], tx, ty), px, py, cam_h, sdx[i], sdy[i], s[i].k, depth);
        }
      }
    for (int q = 0; q < np; ++q)
      if (acc[q].count > 0) sum += acc[q].count * AccumRadiance(acc[q], static_cast<Surf>(keys[q] >> 24), corner_pt[idx[first[q]]].mat);
    return sum / nn;
  }

  // Mean radiance of a pixel that one straight line splits between a plain region of wall w
  // (key wall_key) and a plain region of the floor or ceiling (plane_key), without tracing: the
  // line is where the plane meets the wall's plane, and on which side of it a ray lies is an
  // affine function G of the image point (G > 0: the plane is nearer). Each side is shaded once
  // from its samples' mean light map and the box of their texture coordinates, as PixelPlanes
  // does. -1 when the pixel does not fit (a corner on the wrong side of the line, a ray that
  // does not head towards the plane).
  double PixelSplit(const std::size_t (&idx)[4], std::uint32_t wall_key, std::uint32_t plane_key) const {
    const int w = static_cast<int>(wall_key & 0xFFFFFFu);
    const WallSegment& ws = world.walls[w];
    const bool ceiling = static_cast<Surf>(plane_key >> 24) == Surf::kCeiling;
    if (ceiling && !uniform_ceiling) return -1;
    const double plane_z = ceiling ? frame_ceiling : 0.0;
    const double h_rel = plane_z - cam_h, sgn = ceiling ? 1.0 : -1.0;  // sgn * h_rel > 0
    const double off = ws.along_x ? py - ws.coord : px - ws.coord;       // camera to the wall's plane
    const double off_abs = std::abs(off), perp_sgn = off > 0 ? 1.0 : -1.0;
    double gx[4], gy[4], gz[4], g[4];  // corner directions (world frame, unnormalised) and G
    for (int c = 0; c < 4; ++c) {
      const Eigen::Vector3d& d = corner_dir[idx[c]];
      gx[c] = cyaw * d.x() - syaw * d.y();
      gy[c] = syaw * d.x() + cyaw * d.y();
      gz[c] = d.z();
      if (!(sgn * gz[c] > 0)) return -1;  // every ray of the pixel must head towards the plane
      // The plane point's offset from the wall's plane, times sgn * gz > 0.
      g[c] = off_abs * sgn * gz[c] + std::abs(h_rel) * (ws.along_x ? gy[c] : gx[c]) * perp_sgn;
      if ((g[c] > 0) != (corner_pt[idx[c]].key1 == plane_key)) return -1;
    }
    const SurfPt& pp = corner_pt[idx[std::find_if(g, g + 4, [](double x) { return x > 0; }) - g]];
    const SurfPt& wp = corner_pt[idx[std::find_if(g, g + 4, [](double x) { return x <= 0; }) - g]];
    // Each sample: its side from G, its point on that side's plane (the direction is affine in
    // the image, stepped along the row), the light map there and the box of texture
    // coordinates, as PixelPlanes accumulates them, without the plane intersections' search.
    const double wall_c = ws.coord, wall_p = ws.along_x ? py : px, wall_a = ws.along_x ? px : py;
    double pu_lo = kInf, pu_hi = -kInf, pv_lo = kInf, pv_hi = -kInf, pe = 0;
    double wu_lo = kInf, wu_hi = -kInf, wv_lo = kInf, wv_hi = -kInf, we = 0;
    const int nn = n * n;
    const double inv_n = 1.0 / n;
    // First every sample's direction and side, then each side's samples in a loop of its own
    // (no branch per sample: the light-map reads of several samples overlap).
    int on_plane = 0;
#ifdef SQUINT_RENDER_SIMD
    if (simd) {
      on_plane = avx512 ? SplitSimd(g, gx, gy, gz, h_rel, w, ws.along_x, pu_lo, pu_hi, pv_lo, pv_hi, pe, wu_lo, wu_hi, wv_lo, wv_hi, we)
                        : SplitAvx2(g, gx, gy, gz, h_rel, w, ws.along_x, pu_lo, pu_hi, pv_lo, pv_hi, pe, wu_lo, wu_hi, wv_lo, wv_hi, we);
    } else
#endif
    {
    double sdx[kMaxSamples], sdy[kMaxSamples], sdz[kMaxSamples];
    int on_list[kMaxSamples], off_list[kMaxSamples];
    int off_plane = 0;
    for (int j = 0, k = 0; j < n; ++j) {
      const double fy = (j + 0.5) * inv_n;
      const double g_l = g[0] + fy * (g[2] - g[0]), g_r = g[1] + fy * (g[3] - g[1]);
      const double x_l = gx[0] + fy * (gx[2] - gx[0]), x_r = gx[1] + fy * (gx[3] - gx[1]);
      const double y_l = gy[0] + fy * (gy[2] - gy[0]), y_r = gy[1] + fy * (gy[3] - gy[1]);
      const double z_l = gz[0] + fy * (gz[2] - gz[0]), z_r = gz[1] + fy * (gz[3] - gz[1]);
      for (int i = 0; i < n; ++i, ++k) {
        const double fx = (i + 0.5) * inv_n;
        sdx[k] = x_l + fx * (x_r - x_l), sdy[k] = y_l + fx * (y_r - y_l), sdz[k] = z_l + fx * (z_r - z_l);
        const bool on = g_l + fx * (g_r - g_l) > 0;
        on_list[on_plane] = k, off_list[off_plane] = k;
        on_plane += on, off_plane += !on;
      }
    }
    for (int q = 0; q < on_plane; ++q) {
      const int k = on_list[q];
      const double t = h_rel / sdz[k], x = px + t * sdx[k], y = py + t * sdy[k];
      pu_lo = std::min(pu_lo, x), pu_hi = std::max(pu_hi, x), pv_lo = std::min(pv_lo, y), pv_hi = std::max(pv_hi, y);
      pe += cells[GridIndex(x, y)].irr;
    }
    const double* across = ws.along_x ? sdy : sdx;
    const double* other = ws.along_x ? sdx : sdy;
    for (int q = 0; q < off_plane; ++q) {
      const int k = off_list[q];
      const double t = (wall_c - wall_p) / across[k];
      const double along = wall_a + t * other[k], z = cam_h + t * sdz[k];
      wu_lo = std::min(wu_lo, along), wu_hi = std::max(wu_hi, along), wv_lo = std::min(wv_lo, z), wv_hi = std::max(wv_hi, z);
      we += WallIrradiance(w, along, z);
    }
    }
    const int pn = on_plane, wn = nn - on_plane;
    double sum = 0;
    if (on_plane > 0) {
      const MatFast& m = mats[pp.mat];
      const double e = pe / pn;
      sum += on_plane * (tex[pp.mat].BoxMean(pu_lo, pu_hi, pv_lo, pv_hi) * m.albedo * (ceiling ? world.ambient + kCeilingBounce * e : e) + m.emission);
    }
    if (on_plane < nn) {
      const MatFast& m = mats[wp.mat];
      sum += (nn - on_plane) * (tex[wp.mat].BoxMean(wu_lo, wu_hi, wv_lo, wv_hi) * (m.albedo * (we / wn) + m.emission));
    }
    return sum / nn;
  }

  // Whether an obstacle listed in column u may show in the pixel with corners idx, whose
  // surfaces lie within r_max: its distance range against r_max, its height range against the
  // heights of the pixel's rays over that distance (corner slopes, with a margin).
  bool ObstacleMayShow(int u, const std::size_t (&idx)[4], double r_max) const {
    const int cnt = col_nobs[u];
    if (cnt < 0) return true;
    double k_lo = kInf, k_hi = -kInf;
    for (std::size_t i : idx) k_lo = std::min(k_lo, static_cast<double>(corners[i].k)), k_hi = std::max(k_hi, static_cast<double>(corners[i].k));
    const int* list = &col_obs[static_cast<std::size_t>(u) * kMaxColObstacles];
    for (int i = 0; i < cnt; ++i) {
      const int o = list[i];
      const double t0 = obs_near[o], t1 = std::min(obs_far[o], r_max);
      if (t0 > r_max) continue;
      const double z_lo = cam_h + std::min(k_lo * t0, k_lo * t1) - 0.02, z_hi = cam_h + std::max(k_hi * t0, k_hi * t1) + 0.02;
      const Obstacle& ob = world.obstacles[o];
      if (z_hi >= ob.z0 && z_lo <= ob.z1) return true;
    }
    return false;
  }

  // Mean radiance of pixel (u, v) whose samples start at s, from its corners when they allow.
  double PixelAdaptive(int u, int v, const Sample* s) const {
    const int cw = camera.width + 1;
    const std::size_t i0 = static_cast<std::size_t>(v) * cw + u;
    const std::size_t idx[4] = {i0, i0 + 1, i0 + cw, i0 + cw + 1};
    const SurfPt& p0 = corner_pt[i0];
    bool same_plane = true, same_region = true;
    double r_max = 0, shade_lo = kInf, shade_hi = 0;
    for (std::size_t i : idx) {
      const SurfPt& p = corner_pt[i];
      if (p.exact) return PixelTraced(s);
      same_plane = same_plane && p.key1 == p0.key1;
      same_region = same_region && p.key2 == p0.key2;
      r_max = std::max(r_max, corner_r[i]);
      shade_lo = std::min(shade_lo, p.a), shade_hi = std::max(shade_hi, p.a);
    }
    const std::uint8_t m = mask[static_cast<std::size_t>(v) * camera.width + u];
    if (col_near[u] <= r_max && ObstacleMayShow(u, idx, r_max)) return PixelTraced(s);
    if (!same_plane || (m & kMaskGeometry)) return PixelPlanes(s, idx, (m & kMaskGeometry) != 0, (m & kMaskPattern) != 0);
    if (!same_region || (m & kMaskPattern)) return PixelOnPlane(s, p0.key1);
    const bool plain = (p0.key2 & 0xFFFFu) == 0;
    if (!plain && shade_hi > kMaxShadeRatio * shade_lo && p0.mat >= 0) return PixelOnPlane(s, p0.key1);
    if (p0.mat < 0) return p0.b;
    // One region of one plane: the box-filtered texture over the corners' footprint.
    double u_lo = kInf, u_hi = -kInf, v_lo = kInf, v_hi = -kInf, a_sum = 0;
    for (std::size_t i : idx) {
      const SurfPt& p = corner_pt[i];
      u_lo = std::min(u_lo, p.tu), u_hi = std::max(u_hi, p.tu);
      v_lo = std::min(v_lo, p.tv), v_hi = std::max(v_hi, p.tv);
      a_sum += p.a;
    }
    const double t = tex[p0.mat].BoxMean(u_lo, u_hi, v_lo, v_hi);
    if (plain) {
      // A plain region: the light map's mean over the footprint's box (summed-area tables), as
      // Describe composes radiance from irradiance.
      const MatFast& mf = mats[p0.mat];
      switch (static_cast<Surf>(p0.key1 >> 24)) {
        case Surf::kFloor: return t * mf.albedo * FloorIrradianceMean(u_lo, u_hi, v_lo, v_hi) + mf.emission;
        case Surf::kCeiling:
          return t * mf.albedo * (world.ambient + kCeilingBounce * FloorIrradianceMean(u_lo, u_hi, v_lo, v_hi)) + mf.emission;
        case Surf::kWall:
          return t * (mf.albedo * WallIrradianceMean(static_cast<int>(p0.key1 & 0xFFFFFFu), u_lo, u_hi, v_lo, v_hi) + mf.emission);
        default: break;
      }
    }
    return t * (0.25 * a_sum) + p0.b;
  }

  // PixelAdaptive for the common pixel (four corners on one plain region of one plane, no mark,
  // no obstacle near) from the compact corner arrays, inline; any other pixel goes to
  // PixelAdaptive. Same arithmetic, same result.
  [[gnu::always_inline]] double PixelAdaptiveFast(int u, int v, const Sample* s) const {
    const int cw = camera.width + 1;
    const std::size_t i0 = static_cast<std::size_t>(v) * cw + u, i2 = i0 + cw;
    const std::uint64_t c = corner_cls[i0];
    const bool one = (c == corner_cls[i0 + 1]) & (c == corner_cls[i2]) & (c == corner_cls[i2 + 1]);
    // bit 63: exact; key2's low 16 bits: decal, flat item or light panel (not plain)
    if (!one || (c & (1ull << 63 | 0xFFFFull)) || mask[static_cast<std::size_t>(v) * camera.width + u])
      return PixelAdaptive(u, v, s);
    if (col_near[u] != kInf) {
      const double r_max = std::max(std::max(corner_r[i0], corner_r[i0 + 1]), std::max(corner_r[i2], corner_r[i2 + 1]));
      if (col_near[u] <= r_max) return PixelAdaptive(u, v, s);
    }
    // A plain region's key2 is its material << 16 (0xFFFF: a light panel, no material).
    const int mat = static_cast<int>((c >> 16) & 0xFFFFu);
    if (mat == 0xFFFF) return corner_pt[i0].b;
    const double u_lo = std::min(std::min(corner_tu[i0], corner_tu[i0 + 1]), std::min(corner_tu[i2], corner_tu[i2 + 1]));
    const double u_hi = std::max(std::max(corner_tu[i0], corner_tu[i0 + 1]), std::max(corner_tu[i2], corner_tu[i2 + 1]));
    const double v_lo = std::min(std::min(corner_tv[i0], corner_tv[i0 + 1]), std::min(corner_tv[i2], corner_tv[i2 + 1]));
    const double v_hi = std::max(std::max(corner_tv[i0], corner_tv[i0 + 1]), std::max(corner_tv[i2], corner_tv[i2 + 1]));
    const double t = tex[mat].BoxMean(u_lo, u_hi, v_lo, v_hi);
    const MatFast& mf = mats[mat];
    switch (static_cast<Surf>(c >> 56)) {
      case Surf::kFloor: return t * mf.albedo * FloorIrradianceMean(u_lo, u_hi, v_lo, v_hi) + mf.emission;
      case Surf::kCeiling:
        return t * mf.albedo * (world.ambient + kCeilingBounce * FloorIrradianceMean(u_lo, u_hi, v_lo, v_hi)) + mf.emission;
      case Surf::kWall:
        return t * (mf.albedo * WallIrradianceMean(static_cast<int>((c >> 32) & 0xFFFFFFu), u_lo, u_hi, v_lo, v_hi) + mf.emission);
      default: return PixelAdaptive(u, v, s);
    }
  }

  void Render(const Pose2& pose, MutableGrayView image, std::uint8_t* label, std::ptrdiff_t label_stride, float* range,
              std::ptrdiff_t range_stride, std::uint64_t frame_id) {
    SQUINT_ENSURE(image.data != nullptr && image.width == camera.width && image.height == camera.height,
                  "Renderer::Render: the image must have the camera's size");
    PrepareFrame(pose);
    if (adaptive) PrepareAdaptive();
    const int nn = n * n;
    const double lut_scale = options.exposure * kGammaLutSize / kGammaLutMax;
    const bool noisy = options.noise_sigma > 0;
    const std::uint64_t key = SplitMix(options.seed ^ SplitMix(frame_id + 0x1234567ull));
    const Sample* s = samples.data();
    if (adaptive && !label && !range) {
      // The pixels' means first, then the response and the noise in a pass of their own (its
      // noise-table reads, 256 KB apart, then overlap instead of waiting behind each pixel).
      double* mean = pix_mean.data();
      for (int v = 0; v < camera.height; ++v)
        for (int u = 0; u < camera.width; ++u, s += nn) *mean++ = PixelAdaptiveFast(u, v, s);
      mean = pix_mean.data();
      for (int v = 0; v < camera.height; ++v, mean += camera.width) {
        std::uint8_t* row = image.Row(v);
        int u = 0;
#ifdef SQUINT_RENDER_SIMD
        if (avx512) u = RespondRowSimd(mean, lut_scale, noisy, key, v, row);
        else if (simd) u = RespondRowAvx2(mean, lut_scale, noisy, key, v, row);
#endif
        for (; u < camera.width; ++u) row[u] = Respond(mean[u], lut_scale, noisy, key, u, v);
      }
      return;
    }
    for (int v = 0; v < camera.height; ++v) {
      std::uint8_t* row = image.Row(v);
      for (int u = 0; u < camera.width; ++u, s += nn) {
        double mean;
        Hit first;
        if (adaptive) {
          mean = PixelAdaptiveFast(u, v, s);
        } else if (nn == 1) {
          double dx, dy;
          first = Trace(*s, dx, dy);
          mean = Shade(first, px, py, cam_h, dx, dy, s->k, has_mirrors ? 0 : 1);
        } else {
          mean = PixelTraced(s);
        }
        row[u] = Respond(mean, lut_scale, noisy, key, u, v);
        if (label || range) {
          const Sample& c = n > 1 ? centres[static_cast<std::size_t>(v) * camera.width + u] : *s;
          double dx, dy;
          const Hit hit = n > 1 ? Trace(c, dx, dy) : first;
          if (label) label[v * label_stride + u] = hit.surf == Surf::kFloor ? kLabelFloor : kLabelStanding;
          if (range) range[v * range_stride + u] = static_cast<float>(hit.r * c.RangePerH());
        }
      }
    }
  }

#ifdef SQUINT_RENDER_SIMD
  // Respond for the pixels of row v, eight per AVX-512 step, with Respond's integer steps (the
  // response table's level, the noise hash, the noise step, the clamp); a pixel whose step is
  // kNoiseExact is left to Respond. Returns how many pixels it wrote (a multiple of eight).
  [[gnu::target("avx512f,avx512vl,avx512dq")]] int RespondRowSimd(const double* mean, double lut_scale, bool noisy, std::uint64_t key,
                                                                 int v, std::uint8_t* row) const {
    const int n8 = camera.width / 8 * 8;
    const __m512i lane = _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 6, 7);
    for (int u = 0; u < n8; u += 8) {
      __m256i li = _mm512_cvttpd_epi32(_mm512_mul_pd(_mm512_loadu_pd(mean + u), _mm512_set1_pd(lut_scale)));
      li = _mm256_max_epi32(_mm256_min_epi32(li, _mm256_set1_epi32(kGammaLutSize - 1)), _mm256_setzero_si256());
      const __m256i level = _mm256_and_si256(_mm256_i32gather_epi32(reinterpret_cast<const int*>(gamma_lut.data()), li, 1), _mm256_set1_epi32(0xFF));
      __m256i step = _mm256_setzero_si256();
      __mmask8 exact = 0;
      if (noisy) {  // SplitMix(key ^ (v * 100003 + u)) per lane
        __m512i x = _mm512_xor_si512(_mm512_set1_epi64(static_cast<long long>(key)), _mm512_add_epi64(_mm512_set1_epi64(static_cast<long long>(static_cast<std::uint64_t>(v) * 100003u + u)), lane));
        x = _mm512_add_epi64(x, _mm512_set1_epi64(static_cast<long long>(0x9E3779B97F4A7C15ull)));
        x = _mm512_mullo_epi64(_mm512_xor_si512(x, _mm512_srli_epi64(x, 30)), _mm512_set1_epi64(static_cast<long long>(0xBF58476D1CE4E5B9ull)));
        x = _mm512_mullo_epi64(_mm512_xor_si512(x, _mm512_srli_epi64(x, 27)), _mm512_set1_epi64(static_cast<long long>(0x94D049BB133111EBull)));
        x = _mm512_xor_si512(x, _mm512_srli_epi64(x, 31));
        const __m256i idx = _mm256_and_si256(_mm512_cvtepi64_epi32(x), _mm256_set1_epi32(0xFFFF));
        step = _mm256_i32gather_epi32(reinterpret_cast<const int*>(noise_steps.data()), idx, 1);
        step = _mm256_srai_epi32(_mm256_slli_epi32(step, 24), 24);  // the low byte, signed
        exact = _mm256_cmpeq_epi32_mask(step, _mm256_set1_epi32(kNoiseExact));
      }
      const __m256i grey = _mm256_max_epi32(_mm256_min_epi32(_mm256_add_epi32(level, step), _mm256_set1_epi32(255)), _mm256_setzero_si256());
      _mm_storel_epi64(reinterpret_cast<__m128i*>(row + u), _mm256_cvtepi32_epi8(grey));
      for (; exact; exact &= static_cast<__mmask8>(exact - 1)) {
        const int k = u + __builtin_ctz(exact);
        row[k] = Respond(mean[k], lut_scale, noisy, key, k, v);
      }
    }
    return n8;
  }
#endif

#ifdef SQUINT_RENDER_SIMD
  // The low 64 bits of a * b per lane (AVX2 has no 64-bit multiply): from 32-bit products.
  [[gnu::target("avx2"), gnu::always_inline]] static inline __m256i MulLo64(__m256i a, __m256i b) {
    const __m256i cross = _mm256_add_epi64(_mm256_mul_epu32(_mm256_srli_epi64(a, 32), b), _mm256_mul_epu32(a, _mm256_srli_epi64(b, 32)));
    return _mm256_add_epi64(_mm256_mul_epu32(a, b), _mm256_slli_epi64(cross, 32));
  }
  // RespondRowSimd, four pixels per AVX2 step (the tables read lane by lane).
  [[gnu::target("avx2")]] int RespondRowAvx2(const double* mean, double lut_scale, bool noisy, std::uint64_t key, int v,
                                             std::uint8_t* row) const {
    const int n4 = camera.width / 4 * 4;
    for (int u = 0; u < n4; u += 4) {
      __m128i li = _mm256_cvttpd_epi32(_mm256_mul_pd(_mm256_loadu_pd(mean + u), _mm256_set1_pd(lut_scale)));
      li = _mm_max_epi32(_mm_min_epi32(li, _mm_set1_epi32(kGammaLutSize - 1)), _mm_setzero_si128());
      alignas(16) int l[4], h[4];
      _mm_store_si128(reinterpret_cast<__m128i*>(l), li);
      const __m128i level = _mm_setr_epi32(gamma_lut[l[0]], gamma_lut[l[1]], gamma_lut[l[2]], gamma_lut[l[3]]);
      __m128i step = _mm_setzero_si128();
      int exact = 0;
      if (noisy) {  // SplitMix(key ^ (v * 100003 + u)) per lane
        __m256i x = _mm256_xor_si256(_mm256_set1_epi64x(static_cast<long long>(key)),
                                     _mm256_add_epi64(_mm256_set1_epi64x(static_cast<long long>(static_cast<std::uint64_t>(v) * 100003u + u)),
                                                      _mm256_setr_epi64x(0, 1, 2, 3)));
        x = _mm256_add_epi64(x, _mm256_set1_epi64x(static_cast<long long>(0x9E3779B97F4A7C15ull)));
        x = MulLo64(_mm256_xor_si256(x, _mm256_srli_epi64(x, 30)), _mm256_set1_epi64x(static_cast<long long>(0xBF58476D1CE4E5B9ull)));
        x = MulLo64(_mm256_xor_si256(x, _mm256_srli_epi64(x, 27)), _mm256_set1_epi64x(static_cast<long long>(0x94D049BB133111EBull)));
        x = _mm256_xor_si256(x, _mm256_srli_epi64(x, 31));
        const __m128i idx = _mm256_castsi256_si128(_mm256_permutevar8x32_epi32(x, _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6)));
        _mm_store_si128(reinterpret_cast<__m128i*>(h), _mm_and_si128(idx, _mm_set1_epi32(0xFFFF)));
        step = _mm_setr_epi32(noise_steps[h[0]], noise_steps[h[1]], noise_steps[h[2]], noise_steps[h[3]]);
        exact = Bits32(_mm_cmpeq_epi32(step, _mm_set1_epi32(kNoiseExact)));
      }
      const __m128i grey = _mm_max_epi32(_mm_min_epi32(_mm_add_epi32(level, step), _mm_set1_epi32(255)), _mm_setzero_si128());
      const int bytes = _mm_cvtsi128_si32(_mm_shuffle_epi8(grey, _mm_setr_epi8(0, 4, 8, 12, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1, -1)));
      std::memcpy(row + u, &bytes, 4);
      for (; exact; exact &= exact - 1) {
        const int k = u + __builtin_ctz(exact);
        row[k] = Respond(mean[k], lut_scale, noisy, key, k, v);
      }
    }
    return n4;
  }
#endif

  // A pixel's grey level from its mean radiance: exposure, response curve, noise keyed by
  // (key, pixel), rounded half up.
  [[gnu::always_inline]] std::uint8_t Respond(double mean, double lut_scale, bool noisy, std::uint64_t key, int u, int v) const {
    const int li = std::min(kGammaLutSize - 1, static_cast<int>(mean * lut_scale));
    const int level = gamma_lut[std::max(0, li)];
    double grey = level;
    if (noisy) {
      const std::uint64_t h = SplitMix(key ^ (static_cast<std::uint64_t>(v) * 100003u + u));
      const int step = noise_steps[h & 0xFFFF];
      if (step != kNoiseExact) return static_cast<std::uint8_t>(std::clamp(level + step, 0, 255));
      grey += options.noise_sigma * normal_table[h & 0xFFFF];
    }
    return static_cast<std::uint8_t>(std::clamp(grey + 0.5, 0.0, 255.0));  // rounds half up (truncation of a non-negative value)
  }
};

Renderer::Renderer(const World& world, const CameraModel& camera, const RenderOptions& options)
    : impl_(std::make_unique<Impl>()) {
  impl_->Init(world, camera, options);
}
Renderer::~Renderer() = default;
Renderer::Renderer(Renderer&&) noexcept = default;
Renderer& Renderer::operator=(Renderer&&) noexcept = default;
const CameraModel& Renderer::Camera() const { return impl_->camera; }
const RenderOptions& Renderer::Options() const { return impl_->options; }

void Renderer::Render(const Pose2& world_T_robot, MutableGrayView image, std::uint8_t* label, std::ptrdiff_t label_stride,
                      float* range_m, std::ptrdiff_t range_stride, std::uint64_t frame_id) {
  impl_->Render(world_T_robot, image, label, label_stride, range_m, range_stride, frame_id);
}

cv::Mat Renderer::Render(const Pose2& world_T_robot, cv::Mat* label, cv::Mat* range_m, std::uint64_t frame_id) {
  const CameraModel& c = impl_->camera;
  cv::Mat image(c.height, c.width, CV_8UC1);
  std::uint8_t* lp = nullptr;
  float* rp = nullptr;
  if (label) {
    label->create(c.height, c.width, CV_8UC1);
    lp = label->ptr<std::uint8_t>();
  }
  if (range_m) {
    range_m->create(c.height, c.width, CV_32FC1);
    rp = range_m->ptr<float>();
  }
  Render(world_T_robot, {image.data, c.width, c.height, static_cast<std::ptrdiff_t>(image.step)}, lp,
         label ? static_cast<std::ptrdiff_t>(label->step) : 0, rp,
         range_m ? static_cast<std::ptrdiff_t>(range_m->step / sizeof(float)) : 0, frame_id);
  return image;
}

}  // namespace squint::sim
