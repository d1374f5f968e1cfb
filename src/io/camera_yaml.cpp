// Camera models from YAML: squint's `camera:` block and ROS camera_info files.
#include "squint/io/camera_yaml.hpp"

#include <yaml-cpp/yaml.h>

#include "squint/core/error.hpp"
#include "yaml_camera_node.hpp"

namespace squint::io {
namespace detail {

double RequireDouble(const YAML::Node& parent, const std::string& key, const std::string& where) {
  const YAML::Node n = parent[key];
  if (!n) throw Error(where + ": missing key '" + key + "'");
  try {
    return n.as<double>();
  } catch (const YAML::Exception&) {
    throw Error(where + ": key '" + key + "' is not a number");
  }
}

namespace {
double OptionalDouble(const YAML::Node& parent, const std::string& key, double fallback, const std::string& where) {
  return parent[key] ? RequireDouble(parent, key, where) : fallback;
}
std::vector<double> DoubleList(const YAML::Node& n, const std::string& key, const std::string& where) {
  if (!n.IsSequence()) throw Error(where + ": '" + key + "' must be a list of numbers");
  std::vector<double> out;
  for (const auto& v : n) {
    try {
      out.push_back(v.as<double>());
    } catch (const YAML::Exception&) {
      throw Error(where + ": '" + key + "' must be a list of numbers");
    }
  }
  return out;
}
}  // namespace

CameraModel ParseCameraNode(const YAML::Node& node, const std::string& where) {
  if (!node || !node.IsMap()) throw Error(where + ": 'camera' must be a map");
  const std::string w = where + ": camera";
  CameraModel c;
  const double width = RequireDouble(node, "width", w), height = RequireDouble(node, "height", w);
  if (width != static_cast<int>(width) || height != static_cast<int>(height))
    throw Error(w + ": width and height must be whole numbers");
  c.width = static_cast<int>(width);
  c.height = static_cast<int>(height);
  c.fx = RequireDouble(node, "fx", w);
  c.fy = RequireDouble(node, "fy", w);
  c.cx = RequireDouble(node, "cx", w);
  c.cy = RequireDouble(node, "cy", w);
  c.height_m = OptionalDouble(node, "height_m", 0.0, w);
  c.pitch_deg = OptionalDouble(node, "pitch_deg", 0.0, w);
  if (node["distortion"] && !node["distortion"].IsNull()) c.distortion = DoubleList(node["distortion"], "distortion", w);
  if (auto why = c.Validate(); !why.empty()) throw Error(w + ": " + why);
  return c;
}

}  // namespace detail

CameraModel LoadCameraYaml(const std::filesystem::path& path, const CameraModel& default_mount) {
  const std::string where = path.string();
  YAML::Node root;
  try {
    root = YAML::LoadFile(path.string());
  } catch (const YAML::BadFile&) {
    throw Error(where + ": cannot open file");
  } catch (const YAML::Exception& e) {
    throw Error(where + ": not valid YAML (line " + std::to_string(e.mark.line + 1) + ")");
  }
  if (!root.IsMap()) throw Error(where + ": expected a YAML map");
  if (root["camera"]) return detail::ParseCameraNode(root["camera"], where);
  if (!root["camera_matrix"]) throw Error(where + ": neither a 'camera' block nor a ROS camera_info ('camera_matrix')");
  // ROS camera_info: image_width, image_height, camera_matrix.data (row-major 3x3),
  // distortion_model + distortion_coefficients.data.
  CameraModel c;
  c.width = static_cast<int>(detail::RequireDouble(root, "image_width", where));
  c.height = static_cast<int>(detail::RequireDouble(root, "image_height", where));
  const YAML::Node k = root["camera_matrix"]["data"];
  if (!k || !k.IsSequence() || k.size() != 9) throw Error(where + ": camera_matrix.data must hold 9 numbers");
  try {
    c.fx = k[0].as<double>();
    c.cx = k[2].as<double>();
    c.fy = k[4].as<double>();
    c.cy = k[5].as<double>();
  } catch (const YAML::Exception&) {
    throw Error(where + ": camera_matrix.data must hold 9 numbers");
  }
  if (root["distortion_model"]) {
    const std::string model = root["distortion_model"].as<std::string>();
    if (model != "plumb_bob" && model != "rational_polynomial")
      throw Error(where + ": distortion_model '" + model + "' is not supported (plumb_bob only)");
  }
  if (const YAML::Node d = root["distortion_coefficients"]["data"]; d && d.IsSequence()) {
    for (std::size_t i = 0; i < d.size() && i < 5; ++i) {
      try {
        c.distortion.push_back(d[i].as<double>());
      } catch (const YAML::Exception&) {
        throw Error(where + ": distortion_coefficients.data must hold numbers");
      }
    }
    if (c.distortion.size() < 4) c.distortion.clear();
  }
  c.height_m = root["mount_height_m"] ? detail::RequireDouble(root, "mount_height_m", where) : default_mount.height_m;
  c.pitch_deg = root["mount_pitch_deg"] ? detail::RequireDouble(root, "mount_pitch_deg", where) : default_mount.pitch_deg;
  if (auto why = c.Validate(); !why.empty()) throw Error(where + ": " + why);
  return c;
}

}  // namespace squint::io
