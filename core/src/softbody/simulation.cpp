// SPDX-License-Identifier: MIT
#include "deepcut/core/softbody/simulation.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "deepcut/core/errors.h"
#include "deepcut/core/parallel.h"

namespace deepcut {
namespace {

bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

void check_synced(const SoftBodyState& state, const Clusters& clusters, const char* what) {
  const std::size_t n = clusters.particle_slots();
  if (state.displacement.size() != n || state.velocity.size() != n || state.goal.size() != n)
    throw Error(ErrorCode::InvalidArgument, std::string(what) + ": the soft-body state has " +
                                                std::to_string(state.displacement.size()) +
                                                " particles, the clusters " + std::to_string(n) +
                                                " (call sync_soft_body after clusters.apply)");
}

void check_posed(const Clusters& clusters, const std::vector<glm::vec3>& posed, const char* what) {
  if (posed.size() != clusters.vertex_count())
    throw Error(ErrorCode::InvalidArgument, std::string(what) + ": " + std::to_string(posed.size()) +
                                                " posed positions for clusters of " +
                                                std::to_string(clusters.vertex_count()) + " vertices");
}

void check_options(const SoftBodyOptions& o) {
  if (!(o.mass > 0.0f) || !std::isfinite(o.mass))
    throw Error(ErrorCode::InvalidArgument,
                "soft body: mass must be positive and finite, got " + std::to_string(o.mass));
  if (!(o.stiffness >= 0.0f) || !std::isfinite(o.stiffness))
    throw Error(ErrorCode::InvalidArgument,
                "soft body: stiffness must be non-negative and finite, got " + std::to_string(o.stiffness));
  if (!(o.damping >= 0.0f) || !std::isfinite(o.damping))
    throw Error(ErrorCode::InvalidArgument,
                "soft body: damping must be non-negative and finite, got " + std::to_string(o.damping));
}

void check_radius(float radius, const char* what) {
  if (!(radius > 0.0f) || !std::isfinite(radius))
    throw Error(
        ErrorCode::InvalidArgument,
        std::string(what) + ": radius must be a positive finite number, got " + std::to_string(radius));
}

float falloff(float d2, float r2) {
  const float f = 1.0f - d2 / r2;
  return f > 0.0f ? f * f : 0.0f;
}

/// exp(A t) for A = [[0, 1], [-k/m, -c/m]], the damped spring x'' = -(k/m) x - (c/m) x'.
/// With s = trace/2 and q^2 = s^2 - det: exp(A t) = e^{st} (C I + S (A - s I)), where
/// C = cosh(qt), S = sinh(qt)/q (cos and sin/|q| when q^2 < 0, 1 and t when q = 0).
/// Computed in double from exponentials of (s +- q) t, which never overflow (s +- q <= 0).
struct Transition {
  double a11, a12, a21, a22;
};

Transition spring_transition(const SoftBodyOptions& o, double t) {
  const double w2 = double(o.stiffness) / o.mass;  // det A
  const double s = -0.5 * double(o.damping) / o.mass;
  const double q2 = s * s - w2;
  double C, S;  // e^{st} cosh(qt), e^{st} sinh(qt)/q (with their limits)
  const double scale = std::sqrt(std::max(std::abs(q2), 1e-300)) * t;
  if (scale < 1e-4) {
    // |q t| tiny: series in q^2 t^2 (covers critical damping exactly).
    const double e = std::exp(s * t);
    C = e * (1.0 + q2 * t * t / 2.0);
    S = e * t * (1.0 + q2 * t * t / 6.0);
  } else if (q2 > 0.0) {
    const double q = std::sqrt(q2);
    const double ep = std::exp((s + q) * t), em = std::exp((s - q) * t);
    C = 0.5 * (ep + em);
    S = (ep - em) / (2.0 * q);
  } else {
    const double w = std::sqrt(-q2);
    const double e = std::exp(s * t);
    C = e * std::cos(w * t);
    S = e * std::sin(w * t) / w;
  }
  // A - sI = [[-s, 1], [-w2, -c/m - s]] = [[-s, 1], [-w2, s]], since trace A = -c/m = 2s.
  return {C - s * S, S, -w2 * S, C + s * S};
}

}  // namespace

SoftBodyState make_soft_body(const Clusters& clusters) {
  SoftBodyState s;
  const std::size_t n = clusters.particle_slots();
  s.displacement.assign(n, glm::vec3(0.0f));
  s.velocity.assign(n, glm::vec3(0.0f));
  s.goal.assign(n, glm::vec3(0.0f));
  return s;
}

void sync_soft_body(SoftBodyState& state, const Clusters& clusters, const ClusterUpdate& update) {
  const std::size_t n = clusters.particle_slots();
  state.displacement.resize(n, glm::vec3(0.0f));
  state.velocity.resize(n, glm::vec3(0.0f));
  state.goal.resize(n, glm::vec3(0.0f));
  for (const auto& c : update.created) {
    if (c.particle >= n) continue;
    if (c.parent < n) {
      state.displacement[c.particle] = state.displacement[c.parent];
      state.velocity[c.particle] = state.velocity[c.parent];
      state.goal[c.particle] = state.goal[c.parent];
    } else {
      state.displacement[c.particle] = state.velocity[c.particle] = state.goal[c.particle] = glm::vec3(0.0f);
    }
  }
  for (std::uint32_t p : update.touched)
    if (p < n && clusters.members(p).empty())
      state.displacement[p] = state.velocity[p] = state.goal[p] = glm::vec3(0.0f);
}

std::vector<glm::vec3> posed_particle_centres(const Clusters& clusters, const std::vector<glm::vec3>& posed) {
  check_posed(clusters, posed, "soft body");
  std::vector<glm::vec3> out(clusters.particle_slots(), glm::vec3(0.0f));
  for (std::uint32_t p = 0; p < out.size(); ++p) {
    const auto& m = clusters.members(p);
    if (m.empty()) continue;
    glm::dvec3 sum(0.0);
    for (std::uint32_t v : m) sum += glm::dvec3(posed[v]);
    out[p] = glm::vec3(sum / double(m.size()));
  }
  return out;
}

std::size_t poke(SoftBodyState& state, const Clusters& clusters, const std::vector<glm::vec3>& posed,
                 const glm::vec3& point, const glm::vec3& impulse, float radius,
                 const SoftBodyOptions& options) {
  check_synced(state, clusters, "poke");
  check_radius(radius, "poke");
  check_options(options);
  if (!finite(point) || !finite(impulse))
    throw Error(ErrorCode::InvalidArgument, "poke: point and impulse must be finite");
  const std::vector<glm::vec3> centres = posed_particle_centres(clusters, posed);
  const float r2 = radius * radius;
  std::size_t reached = 0;
  for (std::uint32_t p = 0; p < centres.size(); ++p) {
    if (clusters.members(p).empty()) continue;
    const glm::vec3 d = centres[p] - point;
    const float w = falloff(glm::dot(d, d), r2);
    if (w <= 0.0f) continue;
    state.velocity[p] += (w / options.mass) * impulse;
    ++reached;
  }
  return reached;
}

std::size_t drag(SoftBodyState& state, const Clusters& clusters, const std::vector<glm::vec3>& posed,
                 const glm::vec3& grab, const glm::vec3& target, float radius) {
  check_synced(state, clusters, "drag");
  check_radius(radius, "drag");
  if (!finite(grab) || !finite(target))
    throw Error(ErrorCode::InvalidArgument, "drag: points must be finite");
  const std::vector<glm::vec3> centres = posed_particle_centres(clusters, posed);
  const float r2 = radius * radius;
  const glm::vec3 offset = target - grab;
  std::size_t grabbed = 0;
  for (std::uint32_t p = 0; p < centres.size(); ++p) {
    state.goal[p] = glm::vec3(0.0f);
    if (clusters.members(p).empty()) continue;
    const glm::vec3 d = centres[p] - grab;
    const float w = falloff(glm::dot(d, d), r2);
    if (w <= 0.0f) continue;
    state.goal[p] = w * offset;
    ++grabbed;
  }
  return grabbed;
}

void release_drag(SoftBodyState& state) { std::fill(state.goal.begin(), state.goal.end(), glm::vec3(0.0f)); }

void step_soft_body(SoftBodyState& state, float dt, const SoftBodyOptions& options) {
  check_options(options);
  if (!(dt >= 0.0f) || !std::isfinite(dt))
    throw Error(ErrorCode::InvalidArgument,
                "soft body: time step must be non-negative and finite, got " + std::to_string(dt));
  if (state.velocity.size() != state.displacement.size() || state.goal.size() != state.displacement.size())
    throw Error(ErrorCode::InvalidArgument, "soft body: state arrays differ in size");
  if (dt == 0.0f) return;
  const Transition m = spring_transition(options, dt);
  const float a11 = float(m.a11), a12 = float(m.a12), a21 = float(m.a21), a22 = float(m.a22);
  glm::vec3* x = state.displacement.data();
  glm::vec3* v = state.velocity.data();
  const glm::vec3* g = state.goal.data();
  for (std::size_t p = 0, n = state.displacement.size(); p < n; ++p) {
    const glm::vec3 y = x[p] - g[p];
    x[p] = g[p] + a11 * y + a12 * v[p];
    v[p] = a21 * y + a22 * v[p];
  }
}

float deformed_positions(const SoftBodyState& state, const Clusters& clusters,
                         const std::vector<glm::vec3>& posed, std::vector<glm::vec3>& out) {
  check_synced(state, clusters, "soft body");
  check_posed(clusters, posed, "soft body");
  out.resize(posed.size());
  const glm::vec3* x = state.displacement.data();
  // Every vertex on its own: parallel chunks (the largest displacement is exact in any order).
  const float max2 = parallel_reduce(
      posed.size(), 16384, 0.0f,
      [&](std::size_t b, std::size_t e) {
        float m2 = 0.0f;
        for (std::size_t v = b; v < e; ++v) {
          glm::vec3 d(0.0f);
          for (const Influence& in : clusters.influences(VertexId(static_cast<std::uint32_t>(v))))
            d += in.weight * x[in.particle];
          out[v] = posed[v] + d;
          m2 = std::max(m2, glm::dot(d, d));
        }
        return m2;
      },
      [](float a, float b) { return std::max(a, b); });
  return std::sqrt(max2);
}

float max_vertex_displacement(const SoftBodyState& state, const Clusters& clusters) {
  check_synced(state, clusters, "soft body");
  const glm::vec3* x = state.displacement.data();
  float max2 = 0.0f;
  for (std::uint32_t v = 0, n = static_cast<std::uint32_t>(clusters.vertex_count()); v < n; ++v) {
    glm::vec3 d(0.0f);
    for (const Influence& in : clusters.influences(VertexId(v))) d += in.weight * x[in.particle];
    max2 = std::max(max2, glm::dot(d, d));
  }
  return std::sqrt(max2);
}

}  // namespace deepcut
