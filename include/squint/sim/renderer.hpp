// Ray-cast grey rendering of a world from a robot pose through the project's CameraModel, with
// per-pixel floor/standing labels and range; allocation-free per frame after construction.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include "squint/core/camera.hpp"
#include "squint/core/image_view.hpp"
#include "squint/core/pose.hpp"
#include "squint/sim/world.hpp"

namespace squint::sim {

struct RenderOptions {
  int supersample = 2;          // n: n×n samples per pixel, box-averaged in linear radiance
  // n >= 3 (undistorted cameras) only: trace the pixel corners first. A pixel whose four corners
  // see one region of one plane (one material; no light panel, decal, flat item, wall edge or
  // obstacle inside) is shaded once from a box-filtered texture and the light map's mean over
  // its footprint (summed-area tables of both); a pixel on
  // several planes or with a pattern edge inside shades its n×n samples on the planes its
  // corners (or, at a wall edge, its samples' bearing-table walls) see, without tracing; near
  // obstacles, mirrors and stepped ceilings its n×n samples are traced in full. Ranges and
  // labels always come from the traced central rays. false: n×n traced samples everywhere.
  bool adaptive = true;
  double exposure = 0.55;       // multiplies radiance before the camera's response curve
  double gamma = 2.2;           // response: grey = 255 * (exposure * radiance)^(1/gamma), clipped
  double noise_sigma = 1.0;     // Gaussian sensor noise, grey levels (after the response)
  std::uint64_t seed = 1;       // noise seed; noise depends only on (seed, frame_id, pixel)
  int angle_bins_per_column = 4;  // horizontal visibility table density (speed vs. exactness)
  std::string Validate() const;   // empty when valid
};

// Label values (SEQUENCE_FORMAT.md): floor (and flat items on it) vs. anything standing.
inline constexpr std::uint8_t kLabelFloor = 0;
inline constexpr std::uint8_t kLabelStanding = 255;

// Renders one world through one camera. Construction precomputes per-pixel rays, light maps
// and texture tables; Render() then allocates nothing. Not thread-safe (one per thread).
class Renderer {
 public:
  // The camera's robot-frame geometry (height, pitch, intrinsics, distortion) is used as is; it
  // sits at the robot's rotation centre (SEQUENCE_FORMAT.md).
  Renderer(const World& world, const CameraModel& camera, const RenderOptions& options = {});
  ~Renderer();
  Renderer(Renderer&&) noexcept;
  Renderer& operator=(Renderer&&) noexcept;

  const CameraModel& Camera() const;
  const RenderOptions& Options() const;

  // Renders the view from world_T_robot into `image` (camera size). `label` (0 floor / 255
  // standing) and `range_m` (distance from the optical centre along each pixel's central ray;
  // +inf never happens: every ray meets floor, ceiling or a wall) are optional, with strides in
  // elements. `frame_id` only keys the noise.
  void Render(const Pose2& world_T_robot, MutableGrayView image, std::uint8_t* label = nullptr,
              std::ptrdiff_t label_stride = 0, float* range_m = nullptr, std::ptrdiff_t range_stride = 0,
              std::uint64_t frame_id = 0);

  // Convenience: allocates and returns the image (and optionally label CV_8U and range CV_32F).
  cv::Mat Render(const Pose2& world_T_robot, cv::Mat* label = nullptr, cv::Mat* range_m = nullptr,
                 std::uint64_t frame_id = 0);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace squint::sim
