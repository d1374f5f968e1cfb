// Camera models from YAML: a sequence.yaml `camera:` block, or a ROS camera_info file.
#pragma once

#include <filesystem>

#include "squint/core/camera.hpp"

namespace squint::io {

// Reads a camera from either a squint sequence.yaml (or any YAML with a top-level `camera:`
// block of the same keys) or a ROS camera_info YAML (image_width, image_height, camera_matrix,
// distortion_coefficients). ROS files carry no mount: height_m and pitch_deg are taken from
// `mount_height_m` / `mount_pitch_deg` when present, else from `default_mount`.
// Throws squint::Error naming the file and the key that is wrong.
CameraModel LoadCameraYaml(const std::filesystem::path& path, const CameraModel& default_mount = {});

}  // namespace squint::io
