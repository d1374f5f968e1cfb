// Internal: parsing a `camera:` YAML block into a CameraModel, with errors naming file and key.
#pragma once

#include <yaml-cpp/yaml.h>

#include <string>

#include "squint/core/camera.hpp"

namespace squint::io::detail {

CameraModel ParseCameraNode(const YAML::Node& node, const std::string& where);
double RequireDouble(const YAML::Node& parent, const std::string& key, const std::string& where);

}  // namespace squint::io::detail
