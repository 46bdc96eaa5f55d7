// A direction no registration pins down (a corridor's axis) still gets a
// little information in ICP's normal matrix: the noise in the normals gives
// every direction some. s²·H⁻¹ then claims a few centimetres along it while
// the true error grows without bound, and the pose is published as good.
//
// One weak scan is common and harmless (a rolling cage looking at the floor):
// the IMU's prediction carries it. What marks a direction as unobserved is
// persistence: most scans of the last couple of seconds weak. The limits and
// the figures that chose them: docs/decisions/unobserved-direction.md.
#pragma once

#include <cstddef>
#include <vector>

#include "core/icp.hpp"

namespace tumble {

struct UnobservedDirectionParams {
  double weak_min_eigenvalue = 0.002;  // Degeneracy::min_eigenvalue below this: a weak scan (0: none is)
  std::size_t window_scans = 20;       // over the last this many registered scans ...
  double enter_fraction = 0.9;         // ... this fraction weak: unobserved, until below half of it
  double sigma_m = 1.0;                // published along the unobserved direction: "unknown", still invertible
};

// Throws std::invalid_argument naming the parameter out of range.
void check_unobserved_direction_params(const UnobservedDirectionParams& params);

// Degeneracy::direction in the covariance's coordinates (rotation in radians).
Vector6d weakest_direction(const Degeneracy& degeneracy);
// Adds sigma_m² to a covariance over (tx, ty, tz, rx, ry, rz) along a
// direction of it (weakest_direction's: unit in the scaled coordinates).
void widen_along(Matrix6d& covariance, const Vector6d& direction, double sigma_m);

class UnobservedDirection {
 public:
  explicit UnobservedDirection(const UnobservedDirectionParams& params);

  // Adds a scan registered on a map; true while the window says a direction is
  // unobserved (for every scan then, weak or not: one scan that happens to pass
  // the bar is not a direction seen again). The window outlives a new local
  // map: the weakness belongs to the place (a corridor loses its map often).
  bool add(const Degeneracy& degeneracy);
  // Whether a scan counts as weak here (weak_min_eigenvalue).
  bool weak(const Degeneracy& degeneracy) const { return degeneracy.min_eigenvalue < params_.weak_min_eigenvalue; }
  // Whether the last add() ended an unobserved spell.
  bool spell_ended() const { return spell_ended_; }
  // From the start of a spell until the window holds no weak scan again:
  // a place where the scans have lately left a direction unpinned.
  bool since_spell() const { return since_spell_; }

  // Adds sigma_m² to a published covariance over (tx, ty, tz, rx, ry, rz)
  // along the weakest direction of the newest weak scan (not the scan's own:
  // one that pins it has its weakest elsewhere), rotation in radians.
  void widen(Matrix6d& covariance) const;

 private:
  UnobservedDirectionParams params_;
  Vector6d direction_ = Vector6d::Zero();  // of the newest weak scan, rotation part in radians
  std::vector<bool> weak_;  // ring over the window
  std::size_t next_ = 0;
  std::size_t filled_ = 0;
  std::size_t weak_count_ = 0;
  bool unobserved_ = false;
  bool spell_ended_ = false;
  bool since_spell_ = false;
};

}  // namespace tumble
