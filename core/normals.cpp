#include "core/normals.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <stdexcept>
#include <string>

namespace tumble {

PlaneFit CovarianceAccumulator::fit(const Eigen::Vector3d& viewpoint, const NormalParams& limits) const {
  PlaneFit fit;
  const Eigen::Vector3d to_sensor = viewpoint - origin_;
  const double to_sensor_norm = to_sensor.norm();
  fit.normal = to_sensor_norm > 0 ? Eigen::Vector3d(to_sensor / to_sensor_norm) : Eigen::Vector3d::UnitZ();
  if (count_ < 3) return fit;
  const Eigen::Vector3d mean = sum_ / count_;
  Eigen::Matrix3d cov = sum_outer_ / count_ - mean * mean.transpose();
  // computeDirect (closed form) loses relative accuracy on badly scaled input;
  // scaling by the trace makes it unit-free.
  const double trace = cov.trace();
  if (!(trace > 0)) return fit;
  cov /= trace;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver;
  solver.computeDirect(cov);
  const Eigen::Vector3d lambda = solver.eigenvalues().cwiseMax(0.0);  // ascending
  const double sum = lambda.sum();
  if (!(sum > 0)) return fit;
  fit.curvature = lambda(0) / sum;
  if (lambda(1) < limits.min_planarity * lambda(2)) {
    fit.line_like = true;
    return fit;
  }
  if (fit.curvature > limits.max_curvature) return fit;
  Eigen::Vector3d n = solver.eigenvectors().col(0).normalized();
  const double cos_incidence = to_sensor_norm > 0 ? n.dot(to_sensor) / to_sensor_norm : 1.0;
  if (std::abs(cos_incidence) < limits.min_cos_incidence) return fit;
  fit.normal = cos_incidence < 0 ? Eigen::Vector3d(-n) : n;
  fit.valid = true;
  return fit;
}

NormalEstimator::NormalEstimator(const NormalParams& params, ParallelRunner& runner)
    : params_(params), runner_(&runner), neighbours_(runner.workers()) {
  if (params.k < 3) throw std::invalid_argument("normal k must be >= 3, got " + std::to_string(params.k));
  if (!(params.max_radius_m > 0)) throw std::invalid_argument("normal max_radius_m must be > 0");
  for (std::vector<Neighbour>& buffer : neighbours_)
    buffer.reserve(2 * static_cast<std::size_t>(std::max(params.k, params.line_retry_k)));
}

void NormalEstimator::index(const PointCloud& cloud) { grid_.build(cloud.points, params_.grid_cell_m); }

void NormalEstimator::fit_point(PointCloud& cloud, const Eigen::Vector3d& viewpoint, std::size_t i,
                                std::vector<Neighbour>& buffer) const {
  auto knn = [&](const Eigen::Vector3d& q, double radius, std::span<Neighbour> out, std::size_t k) {
    return grid_.knn(q, radius, out, k, KnnOrder::kAny);
  };
  auto position = [&](std::uint32_t index) -> const Eigen::Vector3d& { return cloud.points[index]; };
  auto line = [&](std::uint32_t index) -> std::uint32_t { return cloud.rings[index]; };
  store_fit(cloud, i, fit_neighbourhood(cloud.points[i], cloud.rings[i], viewpoint, params_, buffer, knn, position, line));
}

void NormalEstimator::estimate(PointCloud& cloud, const Eigen::Vector3d& viewpoint) {
  index(cloud);
  runner_->run(cloud.size(), [&](std::size_t worker, std::size_t begin, std::size_t end) {
    for (std::size_t i = begin; i < end; ++i) fit_point(cloud, viewpoint, i, neighbours_[worker]);
  });
}

void NormalEstimator::estimate(PointCloud& cloud, const Eigen::Vector3d& viewpoint,
                               std::span<const std::uint32_t> indices) {
  runner_->run(indices.size(), [&](std::size_t worker, std::size_t begin, std::size_t end) {
    for (std::size_t j = begin; j < end; ++j) fit_point(cloud, viewpoint, indices[j], neighbours_[worker]);
  });
}

}  // namespace tumble
