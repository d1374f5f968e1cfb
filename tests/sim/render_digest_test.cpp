// Render digests: one 64-bit FNV-1a hash of image, label and range per view over a wide set of
// views (every built-in world at several sizes, supersampling factors, adaptive and full
// sampling, noise sigmas, with and without labels and ranges; the default building's benchmark
// poses; a distorted camera). Renderer speed-ups must leave every output byte-identical:
//   SQUINT_RENDER_DIGEST=/tmp/render-ref/digests.txt squint_sim_tests --gtest_filter='RenderDigest.*'
// writes the digests (one line per view: name and hash) for `cmp` against those of the code
// before the change. Without the variable the test checks that rendering is deterministic (two
// renderers of one world give the same digests, rendering a view again gives the same bytes).
// A second test compares the renderer's vector paths (AVX-512, AVX2) with its scalar code.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "squint/sim/renderer.hpp"
#include "squint/sim/world.hpp"

namespace squint::sim {
namespace {

std::uint64_t Fnv(std::uint64_t h, const void* data, std::size_t n) {
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 0x100000001B3ull;
  return h;
}

struct Variant {
  std::string name;
  int width, height, supersample;
  bool adaptive;
  double noise;
  bool outputs;  // label and range too
  int poses;     // how many of the world's poses
};

// Poses of a world: its start, then points of its free space (a fixed sequence over its
// bounds), each with a yaw from the sequence.
std::vector<Pose2> WorldPoses(const World& w, int count) {
  std::vector<Pose2> out{w.start};
  const Box2 b = w.Bounds();
  std::uint64_t s = 0x9E3779B97F4A7C15ull;
  auto next = [&] {
    s = s * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<double>(s >> 11) / 9007199254740992.0;
  };
  for (int tries = 0; static_cast<int>(out.size()) < count && tries < 100000; ++tries) {
    const Eigen::Vector2d p(b.x0 + next() * (b.x1 - b.x0), b.y0 + next() * (b.y1 - b.y0));
    const double yaw = (next() * 2 - 1) * 3.14159;
    if (!w.IsFree(p) || w.DistanceToWalls(p) < 0.3 || w.DistanceToObstacles(p) < 0.3) continue;
    out.push_back({p.x(), p.y(), yaw});
  }
  return out;
}

std::vector<Pose2> BenchPoses() {  // bench/sim_bench.cpp's and the adaptive-lighting test's
  std::vector<Pose2> poses;
  for (int i = 0; i < 64; ++i) {
    const double yaw = 0.3 * std::sin(i * 0.7);
    if (i < 32) poses.push_back({1.0 + i * 1.2, 0.3 * std::sin(i * 0.3), yaw});
    else poses.push_back({40.0 + 0.3 * std::sin(i * 0.3), (i - 32) * 0.75, 1.5708 + yaw});
  }
  for (int i = 0; i < 48; ++i) {
    const double yaw = 0.35 * std::sin(i * 0.7);
    poses.push_back(i < 32 ? Pose2{1.0 + i * 1.2, 0.3 * std::sin(i * 0.3), yaw}
                           : Pose2{40.0 + 0.3 * std::sin(i * 0.3), (i - 32) * 0.75, 1.5708 + yaw});
  }
  return poses;
}

// Renders `poses` with variant v and appends one line per view to `lines`.
void Digest(const World& w, const std::string& world_name, const Variant& v, const std::vector<Pose2>& poses,
            const CameraModel* camera, std::vector<std::string>& lines) {
  RenderOptions o;
  o.supersample = v.supersample;
  o.adaptive = v.adaptive;
  o.noise_sigma = v.noise;
  o.seed = 7;
  const CameraModel cam = camera ? *camera : w.camera.Model().Scaled(v.width, v.height);
  Renderer r(w, cam, o);
  std::vector<std::uint8_t> image(static_cast<std::size_t>(cam.width) * cam.height), label(image.size());
  std::vector<float> range(image.size());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    std::fill(label.begin(), label.end(), 0);
    std::fill(range.begin(), range.end(), 0.0f);
    r.Render(poses[i], {image.data(), cam.width, cam.height, cam.width}, v.outputs ? label.data() : nullptr, cam.width,
             v.outputs ? range.data() : nullptr, cam.width, i);
    std::uint64_t h = Fnv(0xCBF29CE484222325ull, image.data(), image.size());
    if (v.outputs) {
      h = Fnv(h, label.data(), label.size());
      h = Fnv(h, range.data(), range.size() * sizeof(float));
    }
    lines.push_back(fmt::format("{} {} {} {:016x}", world_name, v.name, i, h));
  }
}

std::vector<std::string> AllDigests(bool full) {
  std::vector<std::string> lines;
  const std::vector<Variant> variants = {
      {"glance4", 32, 24, 4, true, 1.0, false, 40},      {"glance4-out", 32, 24, 4, true, 1.0, true, 12},
      {"glance4-s0", 32, 24, 4, true, 0.0, false, 12},   {"glance4-s0.3", 32, 24, 4, true, 0.3, false, 12},
      {"glance4-s2.5", 32, 24, 4, true, 2.5, false, 12}, {"glance4-s7.77", 32, 24, 4, true, 7.77, false, 12},
      {"glance4-s40", 32, 24, 4, true, 40, false, 12},   {"glance4-full", 32, 24, 4, false, 1.0, false, 8},
      {"glance3", 32, 24, 3, true, 1.0, false, 12},      {"glance2", 32, 24, 2, true, 1.0, true, 12},
      {"sonar64", 64, 48, 2, true, 1.0, false, 8},       {"f64-4", 64, 48, 4, true, 1.0, true, 6},
      {"f256", 256, 192, 1, true, 1.0, true, 6},
  };
  // (the quick check: a plain building, a mirror world and the obstacle course)
  const std::vector<std::string> worlds =
      full ? BuiltinWorldNames() : std::vector<std::string>{"default", "corridor-5", "obstacle-course"};
  for (const std::string& name : worlds) {
    const World w = LoadWorld(name);
    const std::vector<Pose2> poses = WorldPoses(w, 40);
    for (const Variant& v : variants) {
      if (!full && v.width > 64) continue;
      const int k = std::min<int>(full ? v.poses : 2, static_cast<int>(poses.size()));
      Digest(w, name, v, {poses.begin(), poses.begin() + k}, nullptr, lines);
    }
  }
  const World def = LoadWorld("default");
  std::vector<Pose2> bench = BenchPoses();
  if (!full) bench.resize(4);
  for (const Variant& v : {Variant{"bench-glance4", 32, 24, 4, true, 1.0, false, 0}, Variant{"bench-glance4-s0", 32, 24, 4, true, 0.0, false, 0},
                           Variant{"bench-glance4-out", 32, 24, 4, true, 1.0, true, 0}})
    Digest(def, "default", v, bench, nullptr, lines);
  // A distorted camera (full sampling) and an odd size.
  CameraModel distorted = def.camera.Model().Scaled(48, 36);
  distorted.distortion = {-0.2, 0.05, 0.001, -0.001, 0.0};
  Digest(def, "default", {"distorted", 48, 36, 3, true, 1.0, true, 0}, {bench.begin(), bench.begin() + (full ? 16 : 2)}, &distorted, lines);
  const World course = LoadWorld("obstacle-course");
  std::vector<Pose2> cposes;
  for (int k = 0; k < (full ? 32 : 2); ++k) cposes.push_back({1.0 + k * 0.35, 0.8 * std::sin(k * 0.4), 0.25 * std::sin(k * 0.9)});
  Digest(course, "obstacle-course", {"bench-f256", 256, 192, 1, true, 1.0, true, 0}, cposes, nullptr, lines);
  Digest(course, "obstacle-course", {"bench-c41", 41, 31, 4, true, 1.0, true, 0}, cposes, nullptr, lines);
  return lines;
}

// The renderer's vector paths (taken where the CPU has them: AVX-512, else AVX2) against its
// scalar code (forced by SQUINT_RENDER_NO_SIMD when the renderer is built), and on an AVX-512 CPU
// its AVX2 paths too (SQUINT_RENDER_NO_AVX512): the same bytes over glances of every built-in
// world, with labels and ranges, at two noise sigmas. (Without AVX2 all are scalar.)
TEST(RenderDigest, SimdAndScalarPathsGiveTheSameBytes) {
#if defined(__GNUC__) && defined(__x86_64__)
  const bool avx512 = __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512dq");
  const bool avx2 = __builtin_cpu_supports("avx2");
#else
  const bool avx512 = false, avx2 = false;
#endif
  std::printf("vector path compared with the scalar code: %s%s\n", avx512 ? "AVX-512" : avx2 ? "AVX2" : "none (scalar)",
              avx512 && avx2 ? ", and AVX2" : "");
  for (const std::string& name : BuiltinWorldNames()) {
    const World w = LoadWorld(name);
    const std::vector<Pose2> poses = WorldPoses(w, 6);
    // (sigma 40: noise steps beyond a byte, which the vector response leaves to the scalar code)
    for (const Variant& v : {Variant{"glance4", 32, 24, 4, true, 1.0, true, 0}, Variant{"glance4-s0", 32, 24, 4, true, 0.0, false, 0},
                             Variant{"glance4-s40", 32, 24, 4, true, 40.0, false, 0}, Variant{"f64-4", 64, 48, 4, true, 2.5, false, 0}}) {
      std::vector<std::string> simd, scalar;
      Digest(w, name, v, poses, nullptr, simd);
      ::setenv("SQUINT_RENDER_NO_SIMD", "1", 1);
      Digest(w, name, v, poses, nullptr, scalar);
      ::unsetenv("SQUINT_RENDER_NO_SIMD");
      EXPECT_EQ(simd, scalar) << name << " " << v.name;
      if (avx512 && avx2) {
        std::vector<std::string> simd_avx2;
        ::setenv("SQUINT_RENDER_NO_AVX512", "1", 1);
        Digest(w, name, v, poses, nullptr, simd_avx2);
        ::unsetenv("SQUINT_RENDER_NO_AVX512");
        EXPECT_EQ(simd_avx2, scalar) << name << " " << v.name << " (AVX2)";
      }
    }
  }
}

TEST(RenderDigest, DeterministicOrWritten) {
  const char* out = std::getenv("SQUINT_RENDER_DIGEST");
  if (out && *out) {
    const std::vector<std::string> lines = AllDigests(true);
    std::FILE* f = std::fopen(out, "w");
    ASSERT_NE(f, nullptr) << "cannot write " << out;
    for (const std::string& l : lines) std::fprintf(f, "%s\n", l.c_str());
    std::fclose(f);
    std::printf("%zu view digests written to %s\n", lines.size(), out);
    return;
  }
  const std::vector<std::string> a = AllDigests(false), b = AllDigests(false);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a[i], b[i]);
  // Different noise seeds and sigmas do give different digests (the hash sees the bytes).
  std::size_t distinct = 0;
  for (std::size_t i = 1; i < a.size(); ++i) distinct += a[i].substr(a[i].size() - 16) != a[i - 1].substr(a[i - 1].size() - 16);
  EXPECT_GT(distinct, a.size() / 2);
}

}  // namespace
}  // namespace squint::sim
