// The YAML world format (docs/worlds.md): strict parsing (unknown keys, wrong types and
// non-positive sizes are errors naming the file and entry), default materials, light rows,
// repeated wall features, and chairs expanded into primitives.
#include <yaml-cpp/yaml.h>
#include <fmt/format.h>

#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "squint/core/angles.hpp"
#include "squint/core/error.hpp"
#include "squint/sim/world.hpp"

namespace squint::sim {
namespace {

inline constexpr const char* kWorldFormat = "squint-world/1";

class Parser {
 public:
  Parser(std::string source) : source_(std::move(source)) {}

  [[noreturn]] void Fail(const std::string& where, const std::string& what) const {
    throw Error(fmt::format("{}: {}: {}", source_, where, what));
  }

  void CheckKeys(const YAML::Node& n, const std::string& where, std::initializer_list<const char*> allowed) const {
    if (!n.IsMap()) Fail(where, "must be a mapping");
    for (const auto& kv : n) {
      const std::string key = kv.first.as<std::string>();
      bool ok = false;
      for (const char* a : allowed) ok = ok || key == a;
      if (!ok) {
        std::string list;
        for (const char* a : allowed) list += std::string(list.empty() ? "" : ", ") + a;
        Fail(where, fmt::format("unknown key '{}' (allowed: {})", key, list));
      }
    }
  }

  double Num(const YAML::Node& n, const std::string& where) const {
    if (!n.IsScalar()) Fail(where, "must be a number");
    try {
      const double v = n.as<double>();
      if (!std::isfinite(v)) Fail(where, "must be finite");
      return v;
    } catch (const YAML::Exception&) {
      Fail(where, fmt::format("'{}' is not a number", n.Scalar()));
    }
  }
  double Num(const YAML::Node& m, const char* key, const std::string& where, double def) const {
    return m[key] ? Num(m[key], where + "." + key) : def;
  }
  double Positive(const YAML::Node& m, const char* key, const std::string& where, double def) const {
    const double v = Num(m, key, where, def);
    if (!(v > 0)) Fail(where + "." + key, fmt::format("must be positive (got {})", v));
    return v;
  }
  double NonNegative(const YAML::Node& m, const char* key, const std::string& where, double def) const {
    const double v = Num(m, key, where, def);
    if (v < 0) Fail(where + "." + key, fmt::format("must not be negative (got {})", v));
    return v;
  }
  double Unit(const YAML::Node& m, const char* key, const std::string& where, double def) const {
    const double v = Num(m, key, where, def);
    if (v < 0 || v > 1) Fail(where + "." + key, fmt::format("must lie in [0, 1] (got {})", v));
    return v;
  }
  int Int(const YAML::Node& m, const char* key, const std::string& where, int def, int min_value) const {
    if (!m[key]) return def;
    const double v = Num(m[key], where + "." + key);
    if (v != std::floor(v) || v < min_value || v > 1e6)
      Fail(where + "." + key, fmt::format("must be an integer >= {} (got {})", min_value, v));
    return static_cast<int>(v);
  }
  std::string Str(const YAML::Node& m, const char* key, const std::string& where, const std::string& def) const {
    if (!m[key]) return def;
    if (!m[key].IsScalar()) Fail(where + "." + key, "must be a string");
    return m[key].as<std::string>();
  }
  std::vector<double> Vec(const YAML::Node& m, const char* key, const std::string& where, std::size_t n_min,
                          std::size_t n_max) const {
    const YAML::Node v = m[key];
    const std::string w = where + "." + key;
    if (!v.IsSequence() || v.size() < n_min || v.size() > n_max)
      Fail(w, n_min == n_max ? fmt::format("must be a list of {} numbers", n_min)
                             : fmt::format("must be a list of {} to {} numbers", n_min, n_max));
    std::vector<double> out;
    for (std::size_t i = 0; i < v.size(); ++i) out.push_back(Num(v[i], fmt::format("{}[{}]", w, i)));
    return out;
  }
  Eigen::Vector2d Point(const YAML::Node& m, const char* key, const std::string& where) const {
    if (!m[key]) Fail(where, fmt::format("missing '{}' ([x, y] in metres)", key));
    const auto v = Vec(m, key, where, 2, 2);
    return {v[0], v[1]};
  }

  int MaterialRef(const World& w, const YAML::Node& m, const char* key, const std::string& where, int def) const {
    if (!m[key]) return def;
    const std::string name = Str(m, key, where, "");
    for (std::size_t i = 0; i < w.materials.size(); ++i)
      if (w.materials[i].name == name) return static_cast<int>(i);
    Fail(where + "." + key, fmt::format("unknown material '{}'", name));
  }

  const std::string& Source() const { return source_; }

 private:
  std::string source_;
};

Texture ParseTexture(const Parser& p, const std::string& s, const std::string& where) {
  static const std::map<std::string, Texture> kNames = {
      {"plain", Texture::kPlain},   {"tiles", Texture::kTiles},   {"speckle", Texture::kSpeckle},
      {"carpet", Texture::kCarpet}, {"brick", Texture::kBrick},   {"panels", Texture::kPanels},
      {"poster", Texture::kPoster}, {"window", Texture::kWindow}, {"glass", Texture::kGlass}};
  const auto it = kNames.find(s);
  if (it == kNames.end())
    p.Fail(where, fmt::format("unknown texture '{}' (plain, tiles, speckle, carpet, brick, panels, poster, window, glass)", s));
  return it->second;
}

// Materials every world has; a world's `materials:` may redefine them.
std::vector<Material> DefaultMaterials() {
  auto m = [](const char* name, double albedo, Texture t, double scale, double contrast, double emission = 0.0,
              double mirror = 0.0) { return Material{name, albedo, t, scale, contrast, emission, mirror}; };
  return {
      m("paint", 0.62, Texture::kPlain, 1.0, 0.0),
      m("tiles", 0.50, Texture::kTiles, 0.30, 0.30),
      m("speckle", 0.45, Texture::kSpeckle, 0.50, 0.35),
      m("carpet", 0.28, Texture::kCarpet, 0.50, 0.25),
      m("brick", 0.40, Texture::kBrick, 0.25, 0.35),
      m("panels", 0.55, Texture::kPanels, 1.20, 0.25),
      m("ceiling", 0.75, Texture::kTiles, 0.60, 0.12),
      m("door", 0.30, Texture::kPanels, 0.45, 0.15),
      m("poster", 0.50, Texture::kPoster, 0.60, 0.70),
      m("glass", 0.10, Texture::kGlass, 0.90, 0.40, 0.70),
      m("window", 0.05, Texture::kWindow, 1.20, 0.40, 1.40),
      m("mirror", 0.15, Texture::kPlain, 1.0, 0.0, 0.0, 0.80),
      m("cardboard", 0.45, Texture::kSpeckle, 0.20, 0.15),
      m("metal", 0.35, Texture::kPlain, 1.0, 0.0),
      m("concrete", 0.55, Texture::kSpeckle, 0.30, 0.20),
      m("wood", 0.30, Texture::kPanels, 0.05, 0.20),
      m("plastic", 0.20, Texture::kPlain, 1.0, 0.0),
      m("paper", 0.90, Texture::kPlain, 1.0, 0.0),
      m("mat", 0.15, Texture::kCarpet, 0.10, 0.20),
  };
}

WallFeature::Kind ParseKind(const Parser& p, const std::string& s, const std::string& where) {
  if (s == "door") return WallFeature::Kind::kDoor;
  if (s == "poster") return WallFeature::Kind::kPoster;
  if (s == "glass_door") return WallFeature::Kind::kGlassDoor;
  if (s == "window") return WallFeature::Kind::kWindow;
  if (s == "mirror") return WallFeature::Kind::kMirror;
  p.Fail(where, fmt::format("unknown feature kind '{}' (door, poster, glass_door, window, mirror)", s));
}

WallSide ParseSide(const Parser& p, const std::string& s, const std::string& where) {
  if (s == "left") return WallSide::kLeft;
  if (s == "right") return WallSide::kRight;
  if (s == "from_end") return WallSide::kFromEnd;
  if (s == "to_end") return WallSide::kToEnd;
  p.Fail(where, fmt::format("unknown side '{}' (left, right, from_end, to_end)", s));
}

int FindMaterial(const World& w, const char* name) {
  for (std::size_t i = 0; i < w.materials.size(); ++i)
    if (w.materials[i].name == name) return static_cast<int>(i);
  return -1;
}

}  // namespace

World ParseWorld(const std::string& yaml_text, const std::string& source) {
  Parser p(source);
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw Error(fmt::format("{}: not valid YAML: {}", source, e.what()));
  }
  if (!root.IsMap()) throw Error(fmt::format("{}: a world file must be a YAML mapping", source));
  p.CheckKeys(root, "top level",
              {"format", "name", "ambient", "camera", "robot", "materials", "corridor_defaults", "corridors", "obstacles",
               "floor_items"});
  if (p.Str(root, "format", "top level", "") != kWorldFormat)
    p.Fail("format", fmt::format("must be '{}'", kWorldFormat));

  World w;
  w.source = source;
  w.name = p.Str(root, "name", "top level", std::filesystem::path(source).stem().string());
  w.ambient = p.NonNegative(root, "ambient", "top level", w.ambient);

  if (const YAML::Node c = root["camera"]) {
    p.CheckKeys(c, "camera", {"height_m", "pitch_deg", "hfov_deg", "width", "height"});
    w.camera.height_m = p.Positive(c, "height_m", "camera", w.camera.height_m);
    w.camera.pitch_deg = p.Num(c, "pitch_deg", "camera", w.camera.pitch_deg);
    if (std::abs(w.camera.pitch_deg) >= 80) p.Fail("camera.pitch_deg", "must lie in (-80, 80)");
    w.camera.hfov_deg = p.Positive(c, "hfov_deg", "camera", w.camera.hfov_deg);
    if (w.camera.hfov_deg >= 170) p.Fail("camera.hfov_deg", "must be below 170");
    w.camera.width = p.Int(c, "width", "camera", w.camera.width, 1);
    w.camera.height = p.Int(c, "height", "camera", w.camera.height, 1);
  }
  if (const YAML::Node r = root["robot"]) {
    p.CheckKeys(r, "robot",
                {"radius_m", "max_speed_mps", "max_turn_rate_dps", "start", "body_above_camera_m", "body_grey"});
    w.robot.radius_m = p.Positive(r, "radius_m", "robot", w.robot.radius_m);
    w.robot.max_speed_mps = p.Positive(r, "max_speed_mps", "robot", w.robot.max_speed_mps);
    w.robot.max_turn_rate_dps = p.Positive(r, "max_turn_rate_dps", "robot", w.robot.max_turn_rate_dps);
    w.robot.body_above_camera_m = p.NonNegative(r, "body_above_camera_m", "robot", w.robot.body_above_camera_m);
    w.robot.body_grey = p.Unit(r, "body_grey", "robot", w.robot.body_grey);
    if (r["start"]) {
      const auto s = p.Vec(r, "start", "robot", 2, 3);
      w.start = {s[0], s[1], s.size() > 2 ? DegToRad(s[2]) : 0.0};
    }
  }

  w.materials = DefaultMaterials();
  if (const YAML::Node ms = root["materials"]) {
    if (!ms.IsMap()) p.Fail("materials", "must be a mapping of name -> material");
    for (const auto& kv : ms) {
      const std::string name = kv.first.as<std::string>();
      const std::string where = "materials." + name;
      const YAML::Node m = kv.second;
      p.CheckKeys(m, where, {"base", "albedo", "texture", "scale_m", "contrast", "emission", "mirror"});
      Material mat;
      if (m["base"]) mat = w.materials[p.MaterialRef(w, m, "base", where, 0)];
      mat.name = name;
      mat.albedo = p.Unit(m, "albedo", where, mat.albedo);
      if (m["texture"]) mat.texture = ParseTexture(p, p.Str(m, "texture", where, ""), where + ".texture");
      mat.scale_m = p.Positive(m, "scale_m", where, mat.scale_m);
      mat.contrast = p.Unit(m, "contrast", where, mat.contrast);
      mat.emission = p.NonNegative(m, "emission", where, mat.emission);
      mat.mirror = p.Unit(m, "mirror", where, mat.mirror);
      const int existing = FindMaterial(w, name.c_str());
      if (existing >= 0) w.materials[existing] = mat;
      else w.materials.push_back(mat);
    }
  }

  // Corridor defaults.
  YAML::Node defaults = root["corridor_defaults"];
  if (defaults) p.CheckKeys(defaults, "corridor_defaults", {"width_m", "height_m", "floor", "wall", "ceiling", "lights"});
  else defaults = YAML::Node(YAML::NodeType::Map);
  const double def_width = p.Positive(defaults, "width_m", "corridor_defaults", 2.0);
  const double def_height = p.Positive(defaults, "height_m", "corridor_defaults", 2.8);
  const int def_floor = p.MaterialRef(w, defaults, "floor", "corridor_defaults", FindMaterial(w, "tiles"));
  const int def_wall = p.MaterialRef(w, defaults, "wall", "corridor_defaults", FindMaterial(w, "paint"));
  const int def_ceiling = p.MaterialRef(w, defaults, "ceiling", "corridor_defaults", FindMaterial(w, "ceiling"));
  const YAML::Node def_lights = defaults["lights"];

  const YAML::Node cs = root["corridors"];
  if (!cs || !cs.IsSequence() || cs.size() == 0) p.Fail("corridors", "a non-empty list of corridors is required");
  std::set<std::string> names;
  for (std::size_t i = 0; i < cs.size(); ++i) {
    const YAML::Node c = cs[i];
    std::string where = fmt::format("corridors[{}]", i);
    p.CheckKeys(c, where, {"name", "from", "to", "width_m", "height_m", "floor", "wall", "ceiling", "lights", "features"});
    Corridor cor;
    cor.name = p.Str(c, "name", where, fmt::format("c{}", i));
    where += " '" + cor.name + "'";
    if (!names.insert(cor.name).second) p.Fail(where, "duplicate corridor name");
    cor.from = p.Point(c, "from", where);
    cor.to = p.Point(c, "to", where);
    cor.width_m = p.Positive(c, "width_m", where, def_width);
    cor.height_m = p.Positive(c, "height_m", where, def_height);
    cor.floor_material = p.MaterialRef(w, c, "floor", where, def_floor);
    cor.wall_material = p.MaterialRef(w, c, "wall", where, def_wall);
    cor.ceiling_material = p.MaterialRef(w, c, "ceiling", where, def_ceiling);
    const double len = (cor.to - cor.from).norm();
    const Eigen::Vector2d ax = len > 0 ? Eigen::Vector2d((cor.to - cor.from) / len) : Eigen::Vector2d(1, 0);
    const Eigen::Vector2d left(-ax.y(), ax.x());

    // Lights: the corridor's own block, or the defaults.
    YAML::Node lights = c["lights"] ? c["lights"] : def_lights;
    const std::string lw = c["lights"] ? where + ".lights" : "corridor_defaults.lights";
    if (lights) {
      p.CheckKeys(lights, lw, {"rows", "spacing_m", "offset_m", "size_m", "side_offset_m", "intensity", "off", "off_every"});
      const std::string rows = p.Str(lights, "rows", lw, "centre");
      if (rows != "centre" && rows != "sides" && rows != "none") p.Fail(lw + ".rows", "must be centre, sides or none");
      const double spacing = p.Positive(lights, "spacing_m", lw, 3.0);
      const double offset = p.NonNegative(lights, "offset_m", lw, spacing / 2);
      std::vector<double> size = {0.6, 0.6};
      if (lights["size_m"]) size = p.Vec(lights, "size_m", lw, 2, 2);
      if (!(size[0] > 0) || !(size[1] > 0)) p.Fail(lw + ".size_m", "sizes must be positive");
      const double side = p.NonNegative(lights, "side_offset_m", lw, cor.width_m / 4);
      const double intensity = p.NonNegative(lights, "intensity", lw, 1.0);
      const int off_every = p.Int(lights, "off_every", lw, 0, 0);
      std::set<int> off;
      if (lights["off"]) {
        if (!lights["off"].IsSequence()) p.Fail(lw + ".off", "must be a list of light indices (0 = nearest `from`)");
        for (std::size_t k = 0; k < lights["off"].size(); ++k) {
          const double v = p.Num(lights["off"][k], fmt::format("{}.off[{}]", lw, k));
          if (v < 0 || v != std::floor(v)) p.Fail(fmt::format("{}.off[{}]", lw, k), "must be a non-negative integer");
          off.insert(static_cast<int>(v));
        }
      }
      if (rows != "none") {
        int index = 0;
        for (double s = offset; s <= len + 1e-9; s += spacing, ++index) {
          std::vector<double> laterals = rows == "centre" ? std::vector<double>{0.0} : std::vector<double>{side, -side};
          for (double lat : laterals) {
            Light l;
            l.centre = cor.from + ax * s + left * lat;
            const bool along_x = std::abs(ax.x()) > 0.5;
            l.half_x = (along_x ? size[0] : size[1]) / 2;
            l.half_y = (along_x ? size[1] : size[0]) / 2;
            l.z_m = cor.height_m;
            l.intensity = intensity;
            l.on = !off.count(index) && !(off_every > 0 && index % off_every == off_every - 1);
            l.corridor = static_cast<int>(i);
            w.lights.push_back(l);
          }
        }
      }
    }

    if (const YAML::Node fs = c["features"]) {
      if (!fs.IsSequence()) p.Fail(where + ".features", "must be a list");
      for (std::size_t k = 0; k < fs.size(); ++k) {
        const YAML::Node f = fs[k];
        const std::string fw = fmt::format("{}.features[{}]", where, k);
        p.CheckKeys(f, fw, {"kind", "side", "at_m", "width_m", "height_m", "z_m", "recess_m", "material", "repeat_every_m", "count"});
        WallFeature wf;
        if (!f["kind"]) p.Fail(fw, "missing 'kind'");
        wf.kind = ParseKind(p, p.Str(f, "kind", fw, ""), fw + ".kind");
        if (!f["side"]) p.Fail(fw, "missing 'side' (left, right, from_end, to_end)");
        wf.side = ParseSide(p, p.Str(f, "side", fw, ""), fw + ".side");
        const bool end = wf.side == WallSide::kFromEnd || wf.side == WallSide::kToEnd;
        double dw = 0.9, dh = 2.1, dz = 0.0, dr = 0.0;
        const char* dm = "door";
        switch (wf.kind) {
          case WallFeature::Kind::kDoor: dr = 0.15; break;
          case WallFeature::Kind::kPoster: dw = 0.6, dh = 0.8, dz = 1.2, dm = "poster"; break;
          case WallFeature::Kind::kGlassDoor: dw = end ? cor.width_m : 1.8, dh = std::min(2.2, cor.height_m), dm = "glass"; break;
          case WallFeature::Kind::kWindow: dw = end ? cor.width_m : 2.0, dh = 1.4, dz = 0.9, dm = "window"; break;
          case WallFeature::Kind::kMirror: dw = end ? cor.width_m : 2.0, dh = cor.height_m, dm = "mirror"; break;
        }
        wf.at_m = p.Num(f, "at_m", fw, end ? 0.0 : len / 2);
        wf.width_m = p.Positive(f, "width_m", fw, dw);
        wf.height_m = p.Positive(f, "height_m", fw, dh);
        wf.z_m = p.NonNegative(f, "z_m", fw, dz);
        wf.recess_m = p.NonNegative(f, "recess_m", fw, dr);
        if (wf.kind != WallFeature::Kind::kDoor && wf.recess_m > 0) p.Fail(fw + ".recess_m", "only doors have a recess");
        wf.material = p.MaterialRef(w, f, "material", fw, FindMaterial(w, dm));
        const double every = f["repeat_every_m"] ? p.Positive(f, "repeat_every_m", fw, 1.0) : 0.0;
        const int count = p.Int(f, "count", fw, 1, 1);
        if (count > 1 && every <= 0) p.Fail(fw, "count > 1 needs repeat_every_m");
        for (int r = 0; r < count; ++r) {
          WallFeature copy = wf;
          copy.at_m = wf.at_m + r * every;
          cor.features.push_back(copy);
        }
      }
    }
    w.corridors.push_back(cor);
  }

  if (const YAML::Node os = root["obstacles"]) {
    if (!os.IsSequence()) p.Fail("obstacles", "must be a list");
    for (std::size_t i = 0; i < os.size(); ++i) {
      const YAML::Node o = os[i];
      std::string where = fmt::format("obstacles[{}]", i);
      p.CheckKeys(o, where, {"type", "at", "yaw_deg", "size", "radius_m", "height_m", "material"});
      const std::string type = p.Str(o, "type", where, "");
      where += " (" + type + ")";
      Obstacle ob;
      ob.centre = p.Point(o, "at", where);
      ob.yaw = DegToRad(p.Num(o, "yaw_deg", where, 0.0));
      ob.source = where;
      auto size3 = [&](std::vector<double> def) {
        std::vector<double> s = o["size"] ? p.Vec(o, "size", where, 3, 3) : def;
        for (double v : s)
          if (!(v > 0)) p.Fail(where + ".size", "sizes must be positive");
        return s;
      };
      if (type == "box") {
        const auto s = size3({0.5, 0.4, 0.45});
        ob.half_x = s[0] / 2, ob.half_y = s[1] / 2, ob.z1 = s[2];
        ob.material = p.MaterialRef(w, o, "material", where, FindMaterial(w, "cardboard"));
        w.obstacles.push_back(ob);
      } else if (type == "column" || type == "bin") {
        const bool column = type == "column";
        ob.material = p.MaterialRef(w, o, "material", where, FindMaterial(w, column ? "concrete" : "plastic"));
        ob.z1 = p.Positive(o, "height_m", where, column ? 3.5 : 0.45);
        if (o["size"]) {  // square column
          const auto s = size3({0.4, 0.4, ob.z1});
          ob.half_x = s[0] / 2, ob.half_y = s[1] / 2, ob.z1 = s[2];
        } else {
          ob.shape = Obstacle::Shape::kCylinder;
          ob.radius = p.Positive(o, "radius_m", where, column ? 0.2 : 0.17);
        }
        w.obstacles.push_back(ob);
      } else if (type == "chair") {
        ob.material = p.MaterialRef(w, o, "material", where, FindMaterial(w, "wood"));
        const auto s = size3({0.45, 0.45, 0.9});  // seat depth, seat width, back height
        const double seat_z = 0.45, seat_t = 0.04, leg = 0.02;
        const double c = std::cos(ob.yaw), sn = std::sin(ob.yaw);
        auto place = [&](double lx, double ly) {
          return Eigen::Vector2d(ob.centre.x() + c * lx - sn * ly, ob.centre.y() + sn * lx + c * ly);
        };
        Obstacle seat = ob;
        seat.half_x = s[0] / 2, seat.half_y = s[1] / 2, seat.z0 = seat_z - seat_t, seat.z1 = seat_z;
        w.obstacles.push_back(seat);
        for (int sx = -1; sx <= 1; sx += 2)
          for (int sy = -1; sy <= 1; sy += 2) {
            Obstacle l = ob;
            l.shape = Obstacle::Shape::kCylinder;
            l.radius = leg;
            l.centre = place(sx * (s[0] / 2 - leg), sy * (s[1] / 2 - leg));
            l.z0 = 0, l.z1 = seat_z - seat_t;
            w.obstacles.push_back(l);
          }
        Obstacle back = ob;  // the back rises along the chair's -x edge (it faces +x)
        back.centre = place(-s[0] / 2 + 0.02, 0.0);
        back.half_x = 0.02, back.half_y = s[1] / 2, back.z0 = seat_z, back.z1 = std::max(seat_z + 0.05, s[2]);
        w.obstacles.push_back(back);
      } else {
        p.Fail(where + ".type", "must be box, column, chair or bin");
      }
    }
  }

  if (const YAML::Node fs = root["floor_items"]) {
    if (!fs.IsSequence()) p.Fail("floor_items", "must be a list");
    for (std::size_t i = 0; i < fs.size(); ++i) {
      const YAML::Node f = fs[i];
      std::string where = fmt::format("floor_items[{}]", i);
      p.CheckKeys(f, where, {"type", "at", "yaw_deg", "size", "material"});
      const std::string type = p.Str(f, "type", where, "");
      where += " (" + type + ")";
      if (type != "paper" && type != "mat") p.Fail(where + ".type", "must be paper or mat");
      FlatItem item;
      item.source = where;
      item.centre = p.Point(f, "at", where);
      item.yaw = DegToRad(p.Num(f, "yaw_deg", where, 0.0));
      std::vector<double> s = type == "paper" ? std::vector<double>{0.297, 0.21} : std::vector<double>{1.2, 0.8};
      if (f["size"]) s = p.Vec(f, "size", where, 2, 2);
      if (!(s[0] > 0) || !(s[1] > 0)) p.Fail(where + ".size", "sizes must be positive");
      item.half_x = s[0] / 2, item.half_y = s[1] / 2;
      item.material = p.MaterialRef(w, f, "material", where, FindMaterial(w, type == "paper" ? "paper" : "mat"));
      w.flat_items.push_back(item);
    }
  }

  if (!root["robot"] || !root["robot"]["start"]) {
    // Default start: 1 m into the first corridor, facing along it.
    const Corridor& c = w.corridors.front();
    const double len = (c.to - c.from).norm();
    const Eigen::Vector2d ax = len > 0 ? Eigen::Vector2d((c.to - c.from) / len) : Eigen::Vector2d(1, 0);
    const Eigen::Vector2d s = c.from + ax * std::min(1.0, len / 2);
    w.start = {s.x(), s.y(), std::atan2(ax.y(), ax.x())};
  }
  w.Build();
  return w;
}

World LoadWorld(const std::string& name_or_path) {
  if (const auto text = BuiltinWorldText(name_or_path)) return ParseWorld(*text, "builtin:" + name_or_path);
  const std::filesystem::path path(name_or_path);
  if (!std::filesystem::is_regular_file(path)) {
    std::string names;
    for (const auto& n : BuiltinWorldNames()) names += (names.empty() ? "" : ", ") + n;
    throw Error(fmt::format("{}: no such world file, and not a built-in world ({})", name_or_path, names));
  }
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  if (!in) throw Error(fmt::format("{}: cannot read the world file", name_or_path));
  return ParseWorld(ss.str(), path.string());
}

}  // namespace squint::sim
