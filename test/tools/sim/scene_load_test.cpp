// Scene YAML: the shipped scenes load and look like what they claim to be;
// bad scenes are refused with the key path and the reason.
#include "tools/sim/scene_load.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>
#include <numbers>

namespace tumble::sim {
namespace {

// A path, not string concatenation: GCC 12 at -O2 warns falsely (-Warray-bounds)
// on `std::string(literal) + "/" + name` once <string> comes from the
// precompiled header.
std::string scene_file(const std::string& name) {
  return (std::filesystem::path(TUMBLE_SIM_SCENES_DIR) / name).string();
}

std::string scene_error_of(const std::string& yaml) {
  try {
    parse_scene(YAML::Load(yaml), "bad.yaml");
  } catch (const SimConfigError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(SceneLoad, GarageIsAClosedRoomWithPillarsAndCars) {
  const Scene garage = load_scene(scene_file("garage.yaml"));
  EXPECT_EQ(garage.name(), "garage");
  EXPECT_GE(garage.primitives().size(), 50u);
  // From the lane centre every direction hits something (closed room) within the room's diagonal.
  const Eigen::Vector3d o(0, 0, 1.0);
  for (int i = 0; i < 360; ++i) {
    for (double elev_deg : {-15.0, 0.0, 15.0}) {
      const double az = i * std::numbers::pi / 180, el = elev_deg * std::numbers::pi / 180;
      const Eigen::Vector3d d(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
      const auto hit = garage.cast(o, d, 200.0);
      ASSERT_TRUE(hit) << "az " << i << " el " << elev_deg;
      EXPECT_LT(hit->range_m, 68.0);
    }
  }
  // Straight down: the floor, 1 m.
  const auto floor = garage.cast(o, -Eigen::Vector3d::UnitZ(), 10.0);
  ASSERT_TRUE(floor);
  EXPECT_NEAR(floor->range_m, 1.0, 1e-12);
  EXPECT_NEAR(floor->reflectivity, 0.3, 1e-12);
}

TEST(SceneLoad, CorridorIsDegenerateAlongItsAxis) {
  const Scene corridor = load_scene(scene_file("corridor.yaml"));
  const Eigen::Vector3d o(0, 0, 1.3);
  // Nothing ahead or behind within the lidar's range; walls at 1.2 m on both sides.
  EXPECT_FALSE(corridor.cast(o, Eigen::Vector3d::UnitX(), 150.0));
  EXPECT_FALSE(corridor.cast(o, -Eigen::Vector3d::UnitX(), 150.0));
  const auto left = corridor.cast(o, Eigen::Vector3d::UnitY(), 150.0);
  ASSERT_TRUE(left);
  EXPECT_NEAR(left->range_m, 1.2, 1e-12);
  EXPECT_NEAR(left->normal_w.y(), -1.0, 1e-12);
  // Every surface normal is perpendicular to x: no return constrains x.
  for (int i = 0; i < 1000; ++i) {
    const double az = i * 2 * std::numbers::pi / 1000;
    const Eigen::Vector3d d = Eigen::Vector3d(std::cos(az), std::sin(az), 0.2 * std::sin(7 * az)).normalized();
    if (auto hit = corridor.cast(o, d, 150.0)) {
      EXPECT_NEAR(hit->normal_w.x(), 0.0, 1e-12);
    }
  }
}

TEST(SceneLoad, YardHasGroundAndFarObjects) {
  const Scene yard = load_scene(scene_file("yard.yaml"));
  const Eigen::Vector3d o(5, 5, 1.5);
  EXPECT_FALSE(yard.cast(o, Eigen::Vector3d::UnitZ(), 150.0)) << "open sky";
  const auto ground = yard.cast(o, Eigen::Vector3d(1, 0, -1).normalized(), 150.0);
  ASSERT_TRUE(ground);
  EXPECT_NEAR(ground->range_m, 1.5 * std::sqrt(2.0), 1e-12);
  // The hangar's west face at x = 100, beyond 90 m.
  const auto far = yard.cast({0, -40, 1.5}, Eigen::Vector3d::UnitX(), 150.0);
  ASSERT_TRUE(far);
  EXPECT_NEAR(far->range_m, 100.0, 1e-9);
}

TEST(SceneLoad, RepeatMakesAGrid) {
  const Scene s = parse_scene(YAML::Load(R"(
objects:
  - {type: cylinder, center_m: [0, 0, 1], radius_m: 0.2, height_m: 2, repeat: {count: [3, 2, 1], step_m: [5, 4, 0]}}
)"),
                              "grid.yaml");
  ASSERT_EQ(s.primitives().size(), 6u);
  EXPECT_TRUE(s.primitives().back().pose_w.translation().isApprox(Eigen::Vector3d(10, 4, 1)));
  EXPECT_EQ(s.name(), "grid");
}

TEST(SceneLoad, ErrorsNameTheKeyAndWhy) {
  EXPECT_EQ(scene_error_of("objects: [{type: box, center_m: [0,0,0], size_m: [1, 2]}]"),
            "bad.yaml: objects[0].size_m: must be 3 positive numbers");
  EXPECT_EQ(scene_error_of("objects: [{type: box, center_m: [0,0,0], size_m: [1,1,1]}, "
                     "{type: box, center_m: [0,0,0], size_m: [1, -2, 1]}]"),
            "bad.yaml: objects[1].size_m: must be 3 positive numbers");
  EXPECT_EQ(scene_error_of("objects: [{type: sphere, center_m: [0,0,0]}]"),
            "bad.yaml: objects[0].type: must be one of: plane, box, cylinder (got 'sphere')");
  EXPECT_EQ(scene_error_of("objects: [{type: cylinder, center_m: [0,0,0], height_m: 2}]"),
            "bad.yaml: objects[0].radius_m: missing");
  EXPECT_EQ(scene_error_of("objects: [{type: plane, center_m: [0,0], size_m: [1, 1]}]"),
            "bad.yaml: objects[0].center_m: must be 3 numbers [x, y, z]");
  EXPECT_EQ(scene_error_of("objects: [{type: plane, center_m: [0,0,0], reflectivity: 200}]"),
            "bad.yaml: objects[0].reflectivity: must be in [0, 1]");
  EXPECT_EQ(scene_error_of("objects: [{type: plane, center_m: [0,0,0], colour: red}]"),
            "bad.yaml: objects[0].colour: unknown key (allowed: type name reflectivity material center_m rpy_deg size_m repeat)");
  EXPECT_EQ(scene_error_of("objects: [{type: cylinder, center_m: [0,0,0], radius_m: 1, height_m: 1, axis: [0,0,0]}]"),
            "bad.yaml: objects[0].axis: must be a nonzero vector");
  EXPECT_EQ(scene_error_of("objects: [{type: box, center_m: [0,0,0], size_m: [1,1,1], repeat: {count: [2, 0, 1], step_m: [1,1,1]}}]"),
            "bad.yaml: objects[0].repeat.count: must be 3 integers in [1, 1000] [nx, ny, nz]");
  EXPECT_EQ(scene_error_of("objects: []"), "bad.yaml: objects: must be a non-empty list of objects");
  EXPECT_EQ(scene_error_of("name: x"), "bad.yaml: objects: must be a non-empty list of objects");
  EXPECT_EQ(scene_error_of("objects: [{type: box, center_m: [0, nan, 0], size_m: [1,1,1]}]"),
            "bad.yaml: objects[0].center_m[1]: must be a finite number");
}

TEST(SceneLoad, FileErrorsNameTheFileAndLine) {
  const auto path = std::filesystem::temp_directory_path() / ("tumble_scene_" + std::to_string(::getpid()) + ".yaml");
  {
    std::ofstream out(path);
    out << "objects:\n  - {type: box, center_m: [0, 0, 0]\n";
  }
  try {
    load_scene(path.string());
    ADD_FAILURE() << "a syntax error must be refused";
  } catch (const SimConfigError& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.rfind(path.filename().string() + ": line ", 0), 0u) << what;
  }
  std::filesystem::remove(path);
  EXPECT_THROW(load_scene("/nonexistent/scene.yaml"), SimConfigError);
}

}  // namespace
}  // namespace tumble::sim
