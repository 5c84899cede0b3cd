// SPDX-License-Identifier: MIT
#pragma once
/// @file softbody/simulation.h
/// Soft-body deformation layered on skinning. Each particle of a
/// `Clusters` is a damped spring pulling its displacement back to zero (or to a drag goal);
/// vertices follow the weighted displacement of their particles.
///
/// Frame: displacements live in world space of the *current* pose, like the skinned positions
/// they are added to (the paper computes velocity and displacement for the current pose). So
/// `deformed_positions(state, clusters, posed)` is `posed[v] + sum_p w(v,p) * displacement[p]`,
/// whatever pose `posed` was skinned for: an animating model can be poked, the dent rides on
/// the animation, and once the springs have settled the vertices are exactly the animated ones.
/// Pokes and drags find particles by their centres in the pose they are given.
///
/// Integration is the exact solution of the damped spring over the time step (a 2x2 matrix
/// exponential computed once per step), so any step size is stable and free of NaN.
/// With clusters that follow the operations: docs/library.md, "Soft body".

#include <cstddef>
#include <vector>

#include "deepcut/core/softbody/clustering.h"

namespace deepcut {

struct SoftBodyOptions {
  /// Spring constant of every particle (force per unit displacement). Default 100.
  float stiffness = 100.0f;
  /// Damping of every particle (force per unit velocity). Default 20: with the default mass this
  /// is critical damping (2 * sqrt(stiffness * mass)), so a poke rises and then decays without
  /// overshoot; lower values wobble.
  float damping = 20.0f;
  /// Mass of every particle. Default 1.
  float mass = 1.0f;
};

/// Per-particle state, indexed by particle slot (see `Clusters::particle_slots`).
struct SoftBodyState {
  std::vector<glm::vec3> displacement;  ///< world units, current pose
  std::vector<glm::vec3> velocity;      ///< world units per second
  std::vector<glm::vec3> goal;          ///< where each spring pulls to: zero, or a drag offset
};

/// A soft body at rest for `clusters`.
SoftBodyState make_soft_body(const Clusters& clusters);

/// Follows `Clusters::apply`: particles split off a parent start with the parent's state (no
/// jump), particles seeded from nothing start at rest, and emptied particles are reset.
void sync_soft_body(SoftBodyState& state, const Clusters& clusters, const ClusterUpdate& update);

/// World centre of every particle slot for the pose `posed` (mean of its members' posed
/// positions; the origin for empty slots).
/// @param posed  one position per vertex (size == clusters.vertex_count()).
/// @throws Error{InvalidArgument} on a size mismatch.
std::vector<glm::vec3> posed_particle_centres(const Clusters& clusters, const std::vector<glm::vec3>& posed);

/// A poke: an impulse at `point` that reaches the particles whose posed centre lies within
/// `radius`, scaled by the smooth falloff (1 - (d / radius)^2)^2. Each particle's velocity
/// changes by falloff * impulse / mass.
/// @param posed    the pose the point was picked in (one position per vertex).
/// @param point    world position.  @param impulse  mass * world units per second.
/// @param radius   world units, > 0.
/// @throws Error{InvalidArgument} for a bad radius or options, non-finite vectors, a size
///         mismatch, or a state not synced with the clusters.
/// @returns the number of particles reached (0: the poke missed; the state is unchanged).
std::size_t poke(SoftBodyState& state, const Clusters& clusters, const std::vector<glm::vec3>& posed,
                 const glm::vec3& point, const glm::vec3& impulse, float radius,
                 const SoftBodyOptions& options = {});

/// A drag: the particles whose posed centre lies within `radius` of `grab` are pulled towards
/// an offset of (target - grab) scaled by the same falloff as `poke`, and stay there until
/// `release_drag`. Calling it again (the mouse moved) replaces the previous goals.
/// @throws Error{InvalidArgument} as `poke`.
/// @returns the number of particles grabbed.
std::size_t drag(SoftBodyState& state, const Clusters& clusters, const std::vector<glm::vec3>& posed,
                 const glm::vec3& grab, const glm::vec3& target, float radius);

/// Lets every particle spring back to rest.
void release_drag(SoftBodyState& state);

/// Advances every particle by `dt` seconds (exact damped-spring solution: stable for any dt).
/// @throws Error{InvalidArgument} for a negative or non-finite dt, a non-positive mass or a
///         negative stiffness or damping.
void step_soft_body(SoftBodyState& state, float dt, const SoftBodyOptions& options = {});

/// The displaced vertices: out[v] = posed[v] + sum of w(v,p) * displacement[p].
/// @param posed  one position per vertex (size == clusters.vertex_count()).
/// @param out    resized to posed.size(); may not alias `posed`.
/// @throws Error{InvalidArgument} on a size mismatch or a state not synced with the clusters.
/// @returns the largest vertex displacement length.
/// @note O(memberships), no allocation once `out` has its size.
float deformed_positions(const SoftBodyState& state, const Clusters& clusters,
                         const std::vector<glm::vec3>& posed, std::vector<glm::vec3>& out);

/// Largest vertex displacement length without writing positions (same cost as above).
float max_vertex_displacement(const SoftBodyState& state, const Clusters& clusters);

}  // namespace deepcut
