#include "tools/sim/scene.hpp"

#include <algorithm>
#include <limits>

namespace tumble::sim {

namespace {
constexpr int kLeafSize = 2;
constexpr int kMaxDepth = 64;
}  // namespace

Scene::Scene(std::vector<Primitive> primitives, std::string name)
    : primitives_(std::move(primitives)), name_(std::move(name)) {
  for (int i = 0; i < static_cast<int>(primitives_.size()); ++i)
    (is_bounded(primitives_[static_cast<std::size_t>(i)]) ? bounded_ : unbounded_).push_back(i);
  if (!bounded_.empty()) {
    nodes_.reserve(2 * bounded_.size());
    build(0, static_cast<int>(bounded_.size()));
  }
}

// Median split along the widest axis of the primitive centres; depth stays
// ~log2(n), far below kMaxDepth for any scene that fits in memory.
int Scene::build(int begin, int end) {
  const int index = static_cast<int>(nodes_.size());
  nodes_.emplace_back();
  Aabb box, centres;
  for (int i = begin; i < end; ++i) {
    const Aabb b = world_bounds(primitives_[static_cast<std::size_t>(bounded_[static_cast<std::size_t>(i)])]);
    box.extend(b);
    centres.extend(b.center());
  }
  nodes_[static_cast<std::size_t>(index)].box = box;
  if (end - begin <= kLeafSize) {
    nodes_[static_cast<std::size_t>(index)].first = begin;
    nodes_[static_cast<std::size_t>(index)].count = end - begin;
    return index;
  }
  Eigen::Index axis = 0;
  (centres.max - centres.min).maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  auto centre_on_axis = [&](int prim) {
    return world_bounds(primitives_[static_cast<std::size_t>(prim)]).center()[axis];
  };
  std::nth_element(bounded_.begin() + begin, bounded_.begin() + mid, bounded_.begin() + end,
                   [&](int a, int b) { return centre_on_axis(a) < centre_on_axis(b); });
  build(begin, mid);
  const int right = build(mid, end);
  nodes_[static_cast<std::size_t>(index)].first = right;
  return index;
}

std::optional<Hit> Scene::cast(const Eigen::Vector3d& origin_w, const Eigen::Vector3d& dir_unit_w,
                               double max_range_m) const {
  const Ray ray{origin_w, dir_unit_w};
  double best_t = max_range_m;
  const Primitive* best_prim = nullptr;
  Eigen::Vector3d best_normal = Eigen::Vector3d::Zero();
  auto test = [&](int prim_index) {
    const Primitive& prim = primitives_[static_cast<std::size_t>(prim_index)];
    if (auto h = intersect(prim, ray, best_t)) {
      best_t = h->t_m;
      best_prim = &prim;
      best_normal = h->normal_w;
    }
  };
  for (int i : unbounded_) test(i);

  if (!nodes_.empty()) {
    const Eigen::Vector3d inv_dir = dir_unit_w.cwiseInverse();
    constexpr double kInf = std::numeric_limits<double>::infinity();
    struct Pending {
      int node;
      double t_entry;
    };
    Pending stack[kMaxDepth];
    int top = 0;
    if (const double t = ray_aabb_entry(nodes_[0].box, origin_w, inv_dir, best_t); t < kInf) stack[top++] = {0, t};
    while (top > 0) {
      const Pending pending = stack[--top];
      if (pending.t_entry > best_t) continue;  // a nearer hit was found since it was pushed
      const Node& node = nodes_[static_cast<std::size_t>(pending.node)];
      if (node.count > 0) {
        for (int i = node.first; i < node.first + node.count; ++i) test(bounded_[static_cast<std::size_t>(i)]);
        continue;
      }
      const int left = static_cast<int>(&node - nodes_.data()) + 1;
      const int right = node.first;
      const double t_left = ray_aabb_entry(nodes_[static_cast<std::size_t>(left)].box, origin_w, inv_dir, best_t);
      const double t_right = ray_aabb_entry(nodes_[static_cast<std::size_t>(right)].box, origin_w, inv_dir, best_t);
      // Visit the nearer child first so the farther one is often culled by best_t.
      const bool left_first = t_left <= t_right;
      const double t_far = left_first ? t_right : t_left;
      const double t_near = left_first ? t_left : t_right;
      if (t_far < kInf) stack[top++] = {left_first ? right : left, t_far};
      if (t_near < kInf) stack[top++] = {left_first ? left : right, t_near};
    }
  }
  if (best_prim == nullptr) return std::nullopt;
  return Hit{best_t, best_prim->reflectivity, best_normal, best_prim->material};
}

}  // namespace tumble::sim
