#include "tools/sim/scene_load.hpp"

#include "tools/sim/motion.hpp"
#include "tools/sim/yaml_fields.hpp"

#include <filesystem>

namespace tumble::sim {

namespace {

Eigen::Vector3d read_size(const YAML::Node& obj, const YamlPath& at, int count) {
  const YAML::Node n = obj["size_m"];
  const YamlPath here = at.key("size_m");
  const std::string why = "must be " + std::to_string(count) + " positive numbers";
  if (!n) here.fail("missing (" + why + ")");
  if (!n.IsSequence() || static_cast<int>(n.size()) != count) here.fail(why);
  Eigen::Vector3d size = Eigen::Vector3d::Zero();
  for (int i = 0; i < count; ++i) {
    double v = 0;
    if (!n[static_cast<std::size_t>(i)].IsScalar() || !YAML::convert<double>::decode(n[static_cast<std::size_t>(i)], v) ||
        !(v > 0) || !std::isfinite(v))
      here.fail(why);
    size[i] = v;
  }
  return size;
}

// Rotation taking local z onto the unit axis (the shortest one).
Eigen::Matrix3d rotation_z_to(const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis).toRotationMatrix();
}

double read_reflectivity(const YAML::Node& map, const YamlPath& at, double fallback) {
  const double r = read_double(map, at, "reflectivity", fallback);
  if (r < 0 || r > 1) at.key("reflectivity").fail("must be in [0, 1]");
  return r;
}

// Copies of one object on a grid: repeat: {count: [nx, ny, nz], step_m: [dx, dy, dz]}.
std::vector<Eigen::Vector3d> read_repeat(const YAML::Node& obj, const YamlPath& at) {
  if (!has_key(obj, "repeat")) return {Eigen::Vector3d::Zero()};
  const YAML::Node rep = obj["repeat"];
  const YamlPath here = at.key("repeat");
  check_keys(rep, here, {"count", "step_m"});
  const YAML::Node count = rep["count"];
  if (!count || !count.IsSequence() || count.size() != 3) here.key("count").fail("must be 3 integers >= 1 [nx, ny, nz]");
  int n[3];
  for (std::size_t i = 0; i < 3; ++i) {
    if (!count[i].IsScalar() || !YAML::convert<int>::decode(count[i], n[i]) || n[i] < 1 || n[i] > 1000)
      here.key("count").fail("must be 3 integers in [1, 1000] [nx, ny, nz]");
  }
  const Eigen::Vector3d step = read_vec3(rep, here, "step_m");
  std::vector<Eigen::Vector3d> offsets;
  for (int i = 0; i < n[0]; ++i)
    for (int j = 0; j < n[1]; ++j)
      for (int k = 0; k < n[2]; ++k) offsets.emplace_back(step.cwiseProduct(Eigen::Vector3d(i, j, k)));
  return offsets;
}

Material read_material(const YAML::Node& obj, const YamlPath& at) {
  const std::string m = read_string(obj, at, "material", "diffuse");
  if (m == "diffuse") return Material::Diffuse;
  if (m == "specular") return Material::Specular;
  if (m == "glass") return Material::Glass;
  at.key("material").fail("must be diffuse, specular or glass, got '" + m + "'");
}

Primitive read_object(const YAML::Node& obj, const YamlPath& at, double default_reflectivity) {
  require_map(obj, at);
  const std::string type = read_string(obj, at, "type");
  Primitive p;
  p.name = read_string(obj, at, "name", "");
  p.reflectivity = read_reflectivity(obj, at, default_reflectivity);
  p.material = read_material(obj, at);
  const Eigen::Vector3d centre = read_vec3(obj, at, "center_m");
  p.pose_w = pose_from_xyz_rpy_deg(centre, read_vec3(obj, at, "rpy_deg", Eigen::Vector3d::Zero()));
  if (type == "plane") {
    check_keys(obj, at, {"type", "name", "reflectivity", "material", "center_m", "rpy_deg", "size_m", "repeat"});
    if (has_key(obj, "size_m")) {
      p.shape = Shape::Rectangle;
      p.half_size = 0.5 * read_size(obj, at, 2);
    } else {
      p.shape = Shape::Plane;
      if (has_key(obj, "repeat")) at.key("repeat").fail("an infinite plane (no size_m) cannot be repeated");
    }
  } else if (type == "box") {
    check_keys(obj, at, {"type", "name", "reflectivity", "material", "center_m", "rpy_deg", "size_m", "repeat"});
    p.shape = Shape::Box;
    p.half_size = 0.5 * read_size(obj, at, 3);
  } else if (type == "cylinder") {
    check_keys(obj, at,
               {"type", "name", "reflectivity", "material", "center_m", "rpy_deg", "axis", "radius_m", "height_m", "capped", "repeat"});
    p.shape = Shape::Cylinder;
    p.radius_m = read_positive(obj, at, "radius_m");
    p.half_size.z() = 0.5 * read_positive(obj, at, "height_m");
    p.capped = read_bool(obj, at, "capped", true);
    if (has_key(obj, "axis")) {
      if (has_key(obj, "rpy_deg")) at.key("axis").fail("give either axis or rpy_deg, not both");
      const Eigen::Vector3d axis = read_vec3(obj, at, "axis");
      if (!(axis.norm() > 1e-9)) at.key("axis").fail("must be a nonzero vector");
      p.pose_w.linear() = rotation_z_to(axis.normalized());
    }
  } else {
    at.key("type").fail("must be one of: plane, box, cylinder (got '" + type + "')");
  }
  return p;
}

}  // namespace

Scene parse_scene(const YAML::Node& root, const std::string& source_name) {
  const YamlPath top{source_name, ""};
  check_keys(root, top, {"name", "description", "default_reflectivity", "objects"});
  const std::string name = read_string(root, top, "name", std::filesystem::path(source_name).stem().string());
  const double default_reflectivity = read_double(root, top, "default_reflectivity", 0.5);
  if (default_reflectivity < 0 || default_reflectivity > 1) top.key("default_reflectivity").fail("must be in [0, 1]");
  const YAML::Node objects = root["objects"];
  const YamlPath objects_at = top.key("objects");
  if (!objects || !objects.IsSequence() || objects.size() == 0) objects_at.fail("must be a non-empty list of objects");
  std::vector<Primitive> primitives;
  for (std::size_t i = 0; i < objects.size(); ++i) {
    const YamlPath at = objects_at.index(i);
    const Primitive p = read_object(objects[i], at, default_reflectivity);
    for (const Eigen::Vector3d& offset : read_repeat(objects[i], at)) {
      Primitive copy = p;
      copy.pose_w.translation() += offset;
      primitives.push_back(std::move(copy));
    }
  }
  return Scene(std::move(primitives), name);
}

Scene load_scene(const std::string& yaml_path) {
  return parse_scene(load_yaml_file(yaml_path), std::filesystem::path(yaml_path).filename().string());
}

}  // namespace tumble::sim
