// SPDX-License-Identifier: MIT
/// @file generate/cactus.cpp
/// The rigged test cactus. Each limb (trunk, left arm, right arm) is a tube swept along a spine
/// (straight run, quarter-circle bend, straight run) with a pleated cross-section, closed by two
/// domes that shrink the rings to a pole. The tube frame is rotation-minimising (double
/// reflection, Wang et al. 2008), so the rings never twist. All three limbs share one welded
/// `SurfaceMesh`; UVs and hard rib-valley normals live in the corner attributes.

#include "deepcut/core/generate/cactus.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <string>
#include <utility>
#include <vector>

#include "deepcut/core/errors.h"
#include "generate/cactus_morph.h"
#include "geometry/predicates.h"

namespace deepcut {
namespace {

/// Triangle count of the paper's cactus; resolution scales with sqrt(target / this).
constexpr double kReferenceTriangles = 25300.0;
/// Guard against 32-bit index overflow (and absurd memory use).
constexpr std::size_t kMaxTriangles = 200000000;
/// Relative depth of the pleats: the radius goes from (1 - a) in a valley to (1 + a) on a ridge.
constexpr double kRibAmplitude = 0.08;
constexpr int kTrunkRibs = 12;
constexpr int kArmRibs = 8;
constexpr int kTrunkJoints = 8;
constexpr int kArmJoints = 6;
constexpr float kKeysPerSecond = 24.0f;

/// A spine: a straight run along `first_dir`, a quarter-circle bend of radius `bend_radius`
/// turning towards `second_dir`, then a straight run along `second_dir`. Arc-length
/// parameterised; outside [0, length()] it continues straight along the end tangents.
struct Spine {
  glm::dvec3 origin{0.0};
  glm::dvec3 first_dir{0.0, 1.0, 0.0};   ///< unit
  glm::dvec3 second_dir{0.0, 1.0, 0.0};  ///< unit, perpendicular to first_dir when bending
  double first_length = 0.0;
  double bend_radius = 0.0;  ///< 0: no bend (then second_dir must equal first_dir)
  double second_length = 0.0;

  double bend_length() const { return bend_radius * geometry::kPi * 0.5; }
  double length() const { return first_length + bend_length() + second_length; }

  /// Point `p` and unit tangent `t` at arc length `s`.
  void eval(double s, glm::dvec3& p, glm::dvec3& t) const {
    if (s <= first_length) {
      p = origin + s * first_dir;
      t = first_dir;
      return;
    }
    const glm::dvec3 bend_start = origin + first_length * first_dir;
    if (s <= first_length + bend_length()) {
      const double phi = (s - first_length) / bend_radius;
      p = bend_start + bend_radius * std::sin(phi) * first_dir +
          bend_radius * (1.0 - std::cos(phi)) * second_dir;
      t = std::cos(phi) * first_dir + std::sin(phi) * second_dir;
      return;
    }
    p = bend_start + bend_radius * (first_dir + second_dir) + (s - first_length - bend_length()) * second_dir;
    t = second_dir;
  }
};

/// Arc length along a quarter ellipse, measured from its pole. The ellipse has axial
/// semi-axis `axial` and radial semi-axis `radial`; at angle `beta` from the pole its point is
/// (axial * cos(beta), radial * sin(beta)).
class QuarterEllipse {
 public:
  QuarterEllipse(double axial, double radial) : axial_(axial), radial_(radial), arc_(kSteps + 1, 0.0) {
    glm::dvec2 prev(axial_, 0.0);
    for (int i = 1; i <= kSteps; ++i) {
      const double beta = 0.5 * geometry::kPi * i / kSteps;
      const glm::dvec2 cur(axial_ * std::cos(beta), radial_ * std::sin(beta));
      arc_[i] = arc_[i - 1] + glm::length(cur - prev);
      prev = cur;
    }
  }

  double length() const { return arc_.back(); }

  /// Angle from the pole at which the arc length from the pole is `arc` (clamped).
  double angle_at(double arc) const {
    if (arc <= 0.0) return 0.0;
    if (arc >= length()) return 0.5 * geometry::kPi;
    const auto it = std::upper_bound(arc_.begin(), arc_.end(), arc);
    const auto i = static_cast<int>(it - arc_.begin());  // arc_[i-1] <= arc < arc_[i]
    const double t = (arc - arc_[i - 1]) / (arc_[i] - arc_[i - 1]);
    return 0.5 * geometry::kPi * (i - 1 + t) / kSteps;
  }

  double axial() const { return axial_; }
  double radial() const { return radial_; }

 private:
  static constexpr int kSteps = 1024;
  double axial_, radial_;
  std::vector<double> arc_;
};

/// The generating curve of a limb in (spine coordinate s, tube radius) space: a start dome,
/// the straight body along the whole spine, an end dome.
class Meridian {
 public:
  Meridian(double start_cap, double body, double end_cap, double radius)
      : start_(start_cap, radius), end_(end_cap, radius), body_(body), radius_(radius) {}

  double length() const { return start_.length() + body_ + end_.length(); }

  /// Spine coordinate `s` (negative in the start dome, > body in the end dome) and tube radius
  /// `rho` at meridian arc length `arc` from the start pole.
  void eval(double arc, double& s, double& rho) const {
    if (arc < start_.length()) {
      const double beta = start_.angle_at(arc);
      s = -start_.axial() * std::cos(beta);
      rho = radius_ * std::sin(beta);
    } else if (arc <= start_.length() + body_) {
      s = arc - start_.length();
      rho = radius_;
    } else {
      const double beta = end_.angle_at(length() - arc);
      s = body_ + end_.axial() * std::cos(beta);
      rho = radius_ * std::sin(beta);
    }
  }

 private:
  QuarterEllipse start_, end_;
  double body_, radius_;
};

/// Up to four (joint, weight) pairs before normalisation.
struct Influences {
  std::array<int, 4> joint{{0, 0, 0, 0}};
  std::array<double, 4> weight{{0.0, 0.0, 0.0, 0.0}};
  int count = 0;

  void add(int j, double w) {
    if (w <= 1e-7) return;
    joint[count] = j;
    weight[count] = w;
    ++count;
  }
};

/// Uniform quadratic B-spline centred at 0 (support [-1.5, 1.5], C1, the shifted copies sum to 1).
double quadratic_bspline(double d) {
  d = std::abs(d);
  if (d <= 0.5) return 0.75 - d * d;
  if (d < 1.5) return 0.5 * (1.5 - d) * (1.5 - d);
  return 0.0;
}

/// A chain of joints spaced evenly along a limb's spine. Each joint owns the bone that starts
/// at it; its weight is a quadratic B-spline centred on the middle of that bone, so a vertex
/// gets up to three neighbouring joints (two near the chain's ends, one at the very tips) and
/// the weights vary smoothly along the limb. Basis functions past the ends fold into the end
/// joints; an arm's chain extends one step backwards into the trunk joint it hangs from.
struct ChainRig {
  int first_joint = 0;  ///< skin joint index of the chain's first joint
  int joint_count = 0;
  double start_s = 0.0;   ///< spine coordinate of the first joint
  double spacing = 1.0;   ///< spine distance between joints
  int parent_joint = -1;  ///< skin joint the chain hangs from (-1: none)

  Influences influences(double s) const {
    Influences out;
    const double x = (s - start_s) / spacing;  // in bones; bone i spans [i, i + 1]
    const int lo = parent_joint < 0 ? 0 : -1;  // chain index -1 stands for the parent
    const int hi = joint_count - 1;
    const int nearest = static_cast<int>(std::floor(x));
    std::array<double, 3> w{{0.0, 0.0, 0.0}};  // by chain index relative to `base`
    const int base = std::clamp(nearest - 1, lo, hi);
    for (int i = nearest - 1; i <= nearest + 1; ++i) {
      const int folded = std::clamp(i, lo, hi);
      w[static_cast<std::size_t>(folded - base)] += quadratic_bspline(x - (i + 0.5));  // 0..2
    }
    for (int k = 0; k < 3 && base + k <= hi; ++k) {
      const int i = base + k;
      out.add(i < 0 ? parent_joint : first_joint + i, w[static_cast<std::size_t>(k)]);
    }
    if (out.count == 0) out.add(first_joint, 1.0);
    return out;
  }
};

/// Float weights (heaviest first) that sum to exactly 1 in float in any order; unused slots are
/// (joint 0, weight 0). Weights are quantised to multiples of 2^-24, so every partial sum is exact.
void normalized_weights(const Influences& in, glm::u16vec4& joints, glm::vec4& weights) {
  constexpr double kOne = 16777216.0;  // 2^24
  std::array<int, 4> order{{0, 1, 2, 3}};
  for (int i = 1; i < in.count; ++i)  // insertion sort, heaviest first
    for (int k = i; k > 0 && in.weight[order[k]] > in.weight[order[k - 1]]; --k)
      std::swap(order[k], order[k - 1]);
  double total = 0.0;
  for (int i = 0; i < in.count; ++i) total += in.weight[i];
  std::array<double, 4> q{{kOne, 0.0, 0.0, 0.0}};
  for (int i = 1; i < in.count; ++i) {
    q[i] = std::round(in.weight[order[i]] / total * kOne);
    q[0] -= q[i];
  }
  joints = glm::u16vec4(0);
  weights = glm::vec4(0.0f);
  int slot = 0;
  for (int i = 0; i < in.count; ++i) {
    if (q[i] <= 0.0) continue;
    joints[slot] = static_cast<std::uint16_t>(in.joint[order[i]]);
    weights[slot] = static_cast<float>(q[i] / kOne);
    ++slot;
  }
}

/// Everything needed to sweep one limb.
struct LimbSpec {
  std::string name;
  Spine spine;
  double radius = 1.0;  ///< nominal tube radius (pleats go +-kRibAmplitude around it)
  int ribs = 8;
  int segments_per_rib = 4;
  double start_cap = 0.5;  ///< axial extent of the start dome
  double end_cap = 1.0;    ///< axial extent of the end dome
  /// Where theta = 0 points at the start (unit, normal to the start tangent): the UV seam.
  glm::dvec3 seam_dir{0.0, 0.0, -1.0};
  ChainRig rig;

  int segments() const { return ribs * segments_per_rib; }
  Meridian meridian() const { return Meridian(start_cap, spine.length(), end_cap, radius); }
};

/// Per-vertex and per-corner data gathered while sweeping, written to the attributes at the end.
struct Builder {
  SurfaceMesh mesh;
  std::vector<glm::u16vec4> joints;  ///< per vertex
  std::vector<glm::vec4> weights;    ///< per vertex
  std::vector<glm::vec2> uvs;        ///< per corner
  std::vector<std::uint32_t> slots;  ///< per corner: index into `normals`
  std::vector<glm::vec3> normals;    ///< per normal slot (accumulated, then normalised)
  std::vector<std::uint8_t> fixed;   ///< per normal slot: 1 if analytic (poles), not accumulated
  cactus_morph::VertexOrigin origin;  ///< per vertex: limb and spine coordinate (for the targets)
  std::uint8_t limb = 0;              ///< the limb being swept

  void add_triangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, const glm::vec2& ua,
                    const glm::vec2& ub, const glm::vec2& uc, std::uint32_t sa, std::uint32_t sb,
                    std::uint32_t sc) {
    mesh.add_face(VertexId(a), VertexId(b), VertexId(c));
    uvs.push_back(ua);
    uvs.push_back(ub);
    uvs.push_back(uc);
    slots.push_back(sa);
    slots.push_back(sb);
    slots.push_back(sc);
  }
};

/// Radius factor of the pleated cross-section: (1 - a) in the creased valleys (theta a multiple
/// of 2 pi / ribs), (1 + a) on the rounded ridges between them.
double rib_factor(int ribs, double theta) {
  return 1.0 - kRibAmplitude + 2.0 * kRibAmplitude * std::abs(std::sin(0.5 * ribs * theta));
}

/// Unit-circle directions and radius factors of a limb's cross-section, one per column.
struct Columns {
  std::vector<double> cos_t, sin_t, factor;
};

Columns limb_columns(const LimbSpec& spec) {
  const int seg = spec.segments();
  Columns c{std::vector<double>(seg), std::vector<double>(seg), std::vector<double>(seg)};
  for (int j = 0; j < seg; ++j) {
    const double theta = 2.0 * geometry::kPi * j / seg;
    c.cos_t[j] = std::cos(theta);
    c.sin_t[j] = std::sin(theta);
    c.factor[j] = j % spec.segments_per_rib == 0 ? 1.0 - kRibAmplitude : rib_factor(spec.ribs, theta);
  }
  return c;
}

/// A limb's rings (poles excluded): centres, tangents, radii and spine coordinates along the
/// meridian (uniform in meridian arc length), and each ring's theta = 0 direction.
struct Rings {
  std::vector<glm::dvec3> centre, tangent, normal;
  std::vector<double> radius, spine_s;
};

/// The theta = 0 directions of `r`'s rings: a rotation-minimising frame by double reflection,
/// starting from the seam direction.
void rotation_minimising_normals(const LimbSpec& spec, Rings& r) {
  const std::size_t rings = r.centre.size();
  r.normal.assign(rings, glm::dvec3(0.0));
  r.normal[0] = glm::normalize(spec.seam_dir - glm::dot(spec.seam_dir, r.tangent[0]) * r.tangent[0]);
  for (std::size_t k = 0; k + 1 < rings; ++k) {
    const glm::dvec3 v1 = r.centre[k + 1] - r.centre[k];
    const double c1 = glm::dot(v1, v1);
    glm::dvec3 n = r.normal[k], t = r.tangent[k];
    if (c1 > 0.0) {
      n -= (2.0 / c1) * glm::dot(v1, n) * v1;
      t -= (2.0 / c1) * glm::dot(v1, t) * v1;
    }
    const glm::dvec3 v2 = r.tangent[k + 1] - t;
    const double c2 = glm::dot(v2, v2);
    if (c2 > 1e-30) n -= (2.0 / c2) * glm::dot(v2, n) * v2;
    r.normal[k + 1] = glm::normalize(n - glm::dot(n, r.tangent[k + 1]) * r.tangent[k + 1]);
  }
}

Rings limb_rings(const LimbSpec& spec, int rings) {
  const Meridian meridian = spec.meridian();
  const double total_arc = meridian.length();
  Rings r{std::vector<glm::dvec3>(rings),
          std::vector<glm::dvec3>(rings),
          {},
          std::vector<double>(rings),
          std::vector<double>(rings)};
  for (int k = 0; k < rings; ++k) {
    meridian.eval(total_arc * (k + 1) / (rings + 1), r.spine_s[k], r.radius[k]);
    spec.spine.eval(r.spine_s[k], r.centre[k], r.tangent[k]);
  }
  rotation_minimising_normals(spec, r);
  return r;
}

/// Appends a limb's vertices to `b`: start pole, rings, end pole, with weights that depend only on
/// the spine coordinate. `t0`, `t1`: the spine's tangents at the poles.
void add_limb_vertices(const LimbSpec& spec, const Columns& columns, const Rings& r, Builder& b,
                       glm::dvec3& t0, glm::dvec3& t1) {
  auto push_weights = [&](double s, int count) {
    glm::u16vec4 j;
    glm::vec4 w;
    normalized_weights(spec.rig.influences(s), j, w);
    b.joints.insert(b.joints.end(), static_cast<std::size_t>(count), j);
    b.weights.insert(b.weights.end(), static_cast<std::size_t>(count), w);
    b.origin.limb.insert(b.origin.limb.end(), static_cast<std::size_t>(count), b.limb);
    b.origin.spine_s.insert(b.origin.spine_s.end(), static_cast<std::size_t>(count), static_cast<float>(s));
  };
  const int seg = spec.segments();
  glm::dvec3 p;
  spec.spine.eval(-spec.start_cap, p, t0);
  b.mesh.add_vertex(glm::vec3(p));
  push_weights(-spec.start_cap, 1);
  for (std::size_t k = 0; k < r.centre.size(); ++k) {
    const glm::dvec3 binormal = glm::cross(r.tangent[k], r.normal[k]);
    for (int j = 0; j < seg; ++j) {
      const glm::dvec3 dir = columns.cos_t[j] * r.normal[k] + columns.sin_t[j] * binormal;
      b.mesh.add_vertex(glm::vec3(r.centre[k] + r.radius[k] * columns.factor[j] * dir));
    }
    push_weights(r.spine_s[k], seg);
  }
  spec.spine.eval(spec.spine.length() + spec.end_cap, p, t1);
  b.mesh.add_vertex(glm::vec3(p));
  push_weights(spec.spine.length() + spec.end_cap, 1);
}

/// A limb's normal slots: one per ring vertex, two (left / right of the crease) in a rib valley,
/// one analytic slot per pole.
struct NormalSlots {
  std::vector<std::uint32_t> column_slot;  ///< per column: its first slot within a ring
  std::vector<std::uint8_t> valley;        ///< per column: 1 in a rib valley
  std::uint32_t per_ring = 0, base = 0, pole0 = 0, pole1 = 0;
  int seg = 0;

  /// The slot of ring k's column j; `side` 1: the corner's face lies in the cell to the right of
  /// column j, 0: to the left.
  std::uint32_t operator()(int k, int j, int side) const {
    const int jj = j % seg;
    return base + per_ring * static_cast<std::uint32_t>(k) + column_slot[jj] +
           (valley[jj] ? static_cast<std::uint32_t>(side) : 0u);
  }
};

/// Lays out a limb's normal slots after those in `b` and sets the poles' analytic normals (the
/// spine's tangents `t0`, `t1` there, outward).
NormalSlots add_normal_slots(const LimbSpec& spec, int rings, const glm::dvec3& t0, const glm::dvec3& t1,
                             Builder& b) {
  NormalSlots s;
  s.seg = spec.segments();
  s.column_slot.resize(s.seg + 1);
  s.valley.resize(s.seg);
  for (int j = 0; j < s.seg; ++j) {
    s.valley[j] = j % spec.segments_per_rib == 0 ? 1 : 0;
    s.column_slot[j] = s.per_ring;
    s.per_ring += s.valley[j] ? 2u : 1u;
  }
  s.base = static_cast<std::uint32_t>(b.normals.size());
  s.pole0 = s.base + s.per_ring * static_cast<std::uint32_t>(rings);
  s.pole1 = s.pole0 + 1;
  b.normals.resize(s.pole1 + 1, glm::vec3(0.0f));
  b.fixed.resize(s.pole1 + 1, 0);
  b.normals[s.pole0] = glm::vec3(-t0);
  b.normals[s.pole1] = glm::vec3(t1);
  b.fixed[s.pole0] = b.fixed[s.pole1] = 1;
  return s;
}

/// Appends a limb's faces to `b`: the start fan, the bands between consecutive rings, the end
/// fan, with their UVs (u around, v along) and normal slots. `vbase`: the start pole's vertex.
void add_limb_faces(int seg, int rings, std::uint32_t vbase, const NormalSlots& slot, Builder& b) {
  const std::uint32_t pole0 = vbase;
  const std::uint32_t pole1 = vbase + 1 + static_cast<std::uint32_t>(rings * seg);
  auto ring_vertex = [&](int k, int j) {
    return vbase + 1 + static_cast<std::uint32_t>(k * seg + (j % seg));
  };
  std::vector<float> u(seg + 1);
  for (int j = 0; j <= seg; ++j) u[j] = static_cast<float>(j) / static_cast<float>(seg);
  std::vector<float> v(rings);
  for (int k = 0; k < rings; ++k) v[k] = static_cast<float>(k + 1) / static_cast<float>(rings + 1);

  // Start fan (outward is -tangent, where the rings run clockwise).
  for (int j = 0; j < seg; ++j) {
    const glm::vec2 pole_uv(0.5f * (u[j] + u[j + 1]), 0.0f);
    b.add_triangle(pole0, ring_vertex(0, j + 1), ring_vertex(0, j), pole_uv, {u[j + 1], v[0]}, {u[j], v[0]},
                   slot.pole0, slot(0, j + 1, 0), slot(0, j, 1));
  }
  // Bands between consecutive rings.
  for (int k = 0; k + 1 < rings; ++k) {
    for (int j = 0; j < seg; ++j) {
      const std::uint32_t a = ring_vertex(k, j), bb = ring_vertex(k, j + 1);
      const std::uint32_t c = ring_vertex(k + 1, j + 1), d = ring_vertex(k + 1, j);
      const glm::vec2 ua(u[j], v[k]), ub(u[j + 1], v[k]), uc(u[j + 1], v[k + 1]), ud(u[j], v[k + 1]);
      const std::uint32_t sa = slot(k, j, 1), sb = slot(k, j + 1, 0);
      const std::uint32_t sc = slot(k + 1, j + 1, 0), sd = slot(k + 1, j, 1);
      b.add_triangle(a, bb, c, ua, ub, uc, sa, sb, sc);
      b.add_triangle(a, c, d, ua, uc, ud, sa, sc, sd);
    }
  }
  // End fan.
  const int last = rings - 1;
  for (int j = 0; j < seg; ++j) {
    const glm::vec2 pole_uv(0.5f * (u[j] + u[j + 1]), 1.0f);
    b.add_triangle(pole1, ring_vertex(last, j), ring_vertex(last, j + 1), pole_uv, {u[j], v[last]},
                   {u[j + 1], v[last]}, slot.pole1, slot(last, j, 1), slot(last, j + 1, 0));
  }
}

/// Sweeps one closed limb with `rings` rings (poles excluded) into `b`.
void sweep_limb(const LimbSpec& spec, int rings, Builder& b) {
  const auto vbase = static_cast<std::uint32_t>(b.mesh.vertex_count());
  glm::dvec3 t0, t1;
  add_limb_vertices(spec, limb_columns(spec), limb_rings(spec, rings), b, t0, t1);
  const NormalSlots slots = add_normal_slots(spec, rings, t0, t1, b);
  add_limb_faces(spec.segments(), rings, vbase, slots, b);
}

/// Makes the glTF rotation sampler of one joint: `amplitude` radians about `axis`, phase-lagged.
AnimationSampler sway_sampler(float seconds, const glm::vec3& axis, float amplitude, float phase) {
  AnimationSampler sampler;
  sampler.components = 4;
  sampler.interpolation = Interpolation::Linear;
  const int intervals = std::max(2, static_cast<int>(std::lround(kKeysPerSecond * seconds)));
  sampler.input.reserve(intervals + 1);
  sampler.output.reserve(4 * (intervals + 1));
  for (int i = 0; i <= intervals; ++i) {
    const float time = seconds * static_cast<float>(i) / static_cast<float>(intervals);
    sampler.input.push_back(i == intervals ? seconds : time);
    const int key = i == intervals ? 0 : i;  // the last key repeats the first: a seamless loop
    const double angle =
        amplitude * std::sin(2.0 * geometry::kPi * key / intervals - static_cast<double>(phase));
    const glm::quat q = glm::angleAxis(static_cast<float>(angle), glm::normalize(axis));
    sampler.output.insert(sampler.output.end(), {q.x, q.y, q.z, q.w});
  }
  return sampler;
}

const glm::dvec3 kUp(0.0, 1.0, 0.0);

void check_options(const CactusOptions& options) {
  if (options.target_triangles < 1000)
    throw Error(ErrorCode::InvalidArgument, "make_cactus: target_triangles " +
                                                std::to_string(options.target_triangles) + " is below 1000");
  if (options.target_triangles > kMaxTriangles)
    throw Error(ErrorCode::InvalidArgument, "make_cactus: target_triangles " +
                                                std::to_string(options.target_triangles) + " is above " +
                                                std::to_string(kMaxTriangles));
  if (!std::isfinite(options.height) || options.height <= 0.0f)
    throw Error(ErrorCode::InvalidArgument,
                "make_cactus: height " + std::to_string(options.height) + " is not a positive number");
  if (!std::isfinite(options.animation_seconds) || options.animation_seconds <= 0.0f)
    throw Error(ErrorCode::InvalidArgument, "make_cactus: animation_seconds " +
                                                std::to_string(options.animation_seconds) +
                                                " is not a positive number");
}

// The trunk and the two arms: spines, radii, pleats, caps and their chains of joints (the
// parent joint of each arm is found with the skeleton).
std::vector<LimbSpec> cactus_limbs(double h, double scale) {
  const glm::dvec3& up = kUp;
  const double trunk_radius = 0.08 * h;
  LimbSpec trunk;
  trunk.name = "trunk";
  trunk.radius = trunk_radius;
  trunk.ribs = kTrunkRibs;
  trunk.segments_per_rib = std::max(2, static_cast<int>(std::lround(5.0 * scale)));
  trunk.start_cap = 0.25 * trunk_radius;  // a flat base standing on y = 0
  trunk.end_cap = trunk_radius;           // a round top reaching y = height
  trunk.spine.origin = glm::dvec3(0.0, trunk.start_cap, 0.0);
  trunk.spine.first_dir = trunk.spine.second_dir = up;
  trunk.spine.first_length = h - trunk.start_cap - trunk.end_cap;
  trunk.seam_dir = glm::dvec3(0.0, 0.0, -1.0);  // the seam runs down the back
  trunk.rig.first_joint = 0;
  trunk.rig.joint_count = kTrunkJoints;
  trunk.rig.spacing = h / kTrunkJoints;
  trunk.rig.start_s = -trunk.start_cap;  // trunk_0 on the ground

  struct ArmParams {
    const char* name;
    glm::dvec3 direction;  // horizontal, away from the trunk
    double height, reach, bend, rise;
    int first_joint;
  };
  const ArmParams arm_params[2] = {
      {"arm_l", glm::normalize(glm::dvec3(-1.0, 0.0, 0.25)), 0.36 * h, 0.11 * h, 0.08 * h, 0.19 * h,
       kTrunkJoints},
      {"arm_r", glm::normalize(glm::dvec3(1.0, 0.0, -0.3)), 0.52 * h, 0.10 * h, 0.075 * h, 0.15 * h,
       kTrunkJoints + kArmJoints},
  };
  std::vector<LimbSpec> limbs{trunk};
  for (const ArmParams& ap : arm_params) {
    LimbSpec arm;
    arm.name = ap.name;
    arm.radius = 0.055 * h;
    arm.ribs = kArmRibs;
    arm.segments_per_rib = std::max(2, static_cast<int>(std::lround(4.0 * scale)));
    arm.start_cap = 0.5 * arm.radius;  // hidden inside the trunk
    arm.end_cap = arm.radius;
    arm.spine.origin = glm::dvec3(0.0, ap.height, 0.0);  // starts on the trunk's axis
    arm.spine.first_dir = ap.direction;
    arm.spine.second_dir = up;
    arm.spine.first_length = ap.reach;
    arm.spine.bend_radius = ap.bend;
    arm.spine.second_length = ap.rise;
    // The seam runs along the side facing away from the viewer (constant under the RMF, as
    // the spine is planar).
    glm::dvec3 side = glm::normalize(glm::cross(ap.direction, up));
    if (side.z > 0.0) side = -side;
    arm.seam_dir = side;
    arm.rig.first_joint = ap.first_joint;
    arm.rig.joint_count = kArmJoints;
    arm.rig.start_s = trunk_radius;  // where the arm leaves the trunk
    arm.rig.spacing = (arm.spine.length() + arm.end_cap - arm.rig.start_s) / kArmJoints;
    limbs.push_back(arm);
  }
  return limbs;
}

// Joint world positions (rest rotations are identity, so world matrices are translations).
struct Skeleton {
  std::vector<glm::dvec3> position;
  std::vector<int> parent;
  std::vector<std::string> name;
};

// The trunk's chain, then each arm's, hung from the trunk joint nearest to where the arm leaves
// the trunk (recorded in the arm's rig).
Skeleton cactus_skeleton(std::vector<LimbSpec>& limbs, double h) {
  Skeleton skeleton;
  auto& joint_pos = skeleton.position;
  auto& joint_parent = skeleton.parent;
  auto& joint_name = skeleton.name;
  joint_pos.resize(kTrunkJoints + 2 * kArmJoints);
  joint_parent.assign(joint_pos.size(), -1);
  joint_name.resize(joint_pos.size());
  for (int i = 0; i < kTrunkJoints; ++i) {
    joint_pos[i] = glm::dvec3(0.0, h * i / kTrunkJoints, 0.0);
    joint_parent[i] = i - 1;
    joint_name[i] = "trunk_" + std::to_string(i);
  }
  for (std::size_t a = 0; a < 2; ++a) {
    LimbSpec& arm = limbs[1 + a];
    glm::dvec3 tangent;
    glm::dvec3 exit_point;
    arm.spine.eval(arm.rig.start_s, exit_point, tangent);
    int nearest = 0;
    for (int i = 1; i < kTrunkJoints; ++i)
      if (glm::length(joint_pos[i] - exit_point) < glm::length(joint_pos[nearest] - exit_point)) nearest = i;
    arm.rig.parent_joint = nearest;
    for (int k = 0; k < kArmJoints; ++k) {
      const int j = arm.rig.first_joint + k;
      arm.spine.eval(arm.rig.start_s + k * arm.rig.spacing, joint_pos[j], tangent);
      joint_parent[j] = k == 0 ? nearest : j - 1;
      joint_name[j] = arm.name + "_" + std::to_string(k);
    }
  }
  return skeleton;
}

// Where the blend shapes act: the trunk's top dome, and each arm from the trunk to its bend's end.
cactus_morph::Shape morph_shape(const std::vector<LimbSpec>& limbs, double h) {
  cactus_morph::Shape shape;
  shape.height = h;
  shape.dome_height = limbs[0].end_cap;
  shape.dome_base_y = limbs[0].spine.origin.y + limbs[0].spine.length();
  for (std::size_t a = 0; a < 2; ++a) {
    const Spine& spine = limbs[1 + a].spine;
    shape.arms[a].start_s = limbs[1 + a].rig.start_s;
    shape.arms[a].full_s = spine.first_length + spine.bend_length();
  }
  return shape;
}

// The swept surface with its skin weights, UVs, area-weighted corner normals and blend shapes.
SurfaceMesh cactus_mesh(const std::vector<LimbSpec>& limbs, double h, std::size_t target_triangles) {
  // Rings are spaced like the columns (square-ish quads), then all ring counts are scaled
  // together so that the total, 2 * sum(segments * rings), meets the target.
  std::vector<double> estimate(limbs.size());
  double estimated_triangles = 0.0;
  for (std::size_t i = 0; i < limbs.size(); ++i) {
    const double spacing = 2.0 * geometry::kPi * limbs[i].radius / limbs[i].segments();
    estimate[i] = limbs[i].meridian().length() / spacing;
    estimated_triangles += 2.0 * limbs[i].segments() * estimate[i];
  }
  const double ring_scale = static_cast<double>(target_triangles) / estimated_triangles;
  std::vector<int> rings(limbs.size());
  std::size_t vertices = 0, triangles = 0, normal_slots = 0;
  for (std::size_t i = 0; i < limbs.size(); ++i) {
    rings[i] = std::max(2, static_cast<int>(std::lround(ring_scale * estimate[i])));
    const auto ring_count = static_cast<std::size_t>(rings[i]);
    vertices += ring_count * limbs[i].segments() + 2;
    triangles += 2u * ring_count * limbs[i].segments();
    normal_slots += ring_count * (limbs[i].segments() + limbs[i].ribs) + 2;
  }

  Builder b;
  b.mesh.reserve(vertices, triangles);
  b.joints.reserve(vertices);
  b.weights.reserve(vertices);
  b.uvs.reserve(3 * triangles);
  b.slots.reserve(3 * triangles);
  b.normals.reserve(normal_slots);
  b.fixed.reserve(normal_slots);
  for (std::size_t i = 0; i < limbs.size(); ++i) {
    b.limb = static_cast<std::uint8_t>(i);
    sweep_limb(limbs[i], rings[i], b);
  }

  // Area-weighted corner normals: each face adds its (unnormalised) normal to its corners' slots.
  const std::vector<glm::vec3>& pos = b.mesh.positions();
  const std::vector<Triangle>& faces = b.mesh.faces();
  for (std::size_t f = 0; f < faces.size(); ++f) {
    const glm::vec3& p0 = pos[faces[f][0].index];
    const glm::vec3 n = glm::cross(pos[faces[f][1].index] - p0, pos[faces[f][2].index] - p0);
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t s = b.slots[3 * f + k];
      if (!b.fixed[s]) b.normals[s] += n;
    }
  }
  for (glm::vec3& n : b.normals) n = glm::normalize(n);

  SurfaceMesh mesh = std::move(b.mesh);
  if (mesh.vertex_count() != b.joints.size() || 3 * mesh.face_slots() != b.uvs.size())
    throw Error(ErrorCode::InvariantViolated, "make_cactus: attribute sizes do not match the mesh");
  mesh.vertex_attrs().add<glm::u16vec4>(attr::kJoints0).data() = std::move(b.joints);
  mesh.vertex_attrs().add<glm::vec4>(attr::kWeights0).data() = std::move(b.weights);
  mesh.corner_attrs().add<glm::vec2>(attr::kUv0).data() = std::move(b.uvs);
  auto& corner_normals = mesh.corner_attrs().add<glm::vec3>(attr::kNormal).data();
  for (std::size_t c = 0; c < corner_normals.size(); ++c) corner_normals[c] = b.normals[b.slots[c]];
  cactus_morph::add_targets(mesh, b.origin, morph_shape(limbs, h), {b.slots, b.normals.size()});
  return mesh;
}

// One sway channel per joint: the trunk sways side to side, the arms bend in their plane.
Animation sway_animation(const std::vector<LimbSpec>& limbs, std::size_t joint_count, int joint_node0, float seconds) {
  const glm::dvec3& up = kUp;
  Animation sway;
  sway.name = "Sway";
  const float deg = static_cast<float>(geometry::kPi / 180.0);
  for (std::size_t j = 0; j < joint_count; ++j) {
    glm::vec3 axis(0.0f, 0.0f, 1.0f);  // the trunk sways side to side
    float amplitude = 1.2f * deg, phase = 0.35f * static_cast<float>(j);
    if (j >= static_cast<std::size_t>(kTrunkJoints)) {
      const std::size_t a = (j - kTrunkJoints) / kArmJoints;
      const std::size_t k = (j - kTrunkJoints) % kArmJoints;
      axis = glm::vec3(glm::cross(limbs[1 + a].spine.first_dir, up));  // arms bend in their plane
      amplitude = 3.0f * deg;
      phase = (a == 0 ? 0.8f : 1.9f) + 0.45f * static_cast<float>(k);
    }
    sway.samplers.push_back(sway_sampler(seconds, axis, amplitude, phase));
    AnimationChannel channel;
    channel.sampler = static_cast<int>(j);
    channel.node = joint_node0 + static_cast<int>(j);
    channel.path = AnimationPath::Rotation;
    sway.channels.push_back(channel);
  }
  return sway;
}

// Node 0 is the cactus, node 1 its mesh, the joints follow.
constexpr int kJointNode0 = 2;

// The nodes: the cactus, its mesh (skinned by skin 0) and the joints of `skeleton`, with the skin.
void add_nodes_and_skin(Model& model, const Skeleton& skeleton) {
  const auto& joint_pos = skeleton.position;
  const auto& joint_parent = skeleton.parent;
  model.nodes.resize(kJointNode0 + joint_pos.size());
  model.nodes[0].name = "Cactus";
  model.nodes[0].children = {1, kJointNode0};
  model.nodes[1].name = "CactusMesh";
  model.nodes[1].mesh = 0;
  model.nodes[1].skin = 0;
  Skin skin;
  skin.name = "CactusSkin";
  skin.skeleton = kJointNode0;
  std::vector<glm::vec3> joint_world(joint_pos.size());  // as a reader composes the float TRS
  for (std::size_t j = 0; j < joint_pos.size(); ++j) {   // parents come before their children
    Node& node = model.nodes[kJointNode0 + j];
    node.name = skeleton.name[j];
    const int parent = joint_parent[j];
    node.translation = glm::vec3(parent < 0 ? joint_pos[j] : joint_pos[j] - joint_pos[parent]);
    joint_world[j] = parent < 0 ? node.translation : joint_world[parent] + node.translation;
    if (parent >= 0) model.nodes[kJointNode0 + parent].children.push_back(kJointNode0 + static_cast<int>(j));
    skin.joints.push_back(kJointNode0 + static_cast<int>(j));
    skin.inverse_bind_matrices.push_back(glm::translate(glm::mat4(1.0f), -joint_world[j]));
  }
  model.skins.push_back(std::move(skin));
}

// The clip: the limbs' sway and, in the same clip, the blend shapes on the mesh's node (their
// sampler after the joints').
void add_animation(Model& model, const std::vector<LimbSpec>& limbs, std::size_t joints, float seconds) {
  model.animations.push_back(sway_animation(limbs, joints, kJointNode0, seconds));
  Animation& clip = model.animations.back();
  clip.samplers.push_back(cactus_morph::weight_sampler(seconds, kKeysPerSecond));
  AnimationChannel weights;
  weights.sampler = static_cast<int>(clip.samplers.size()) - 1;
  weights.node = 1;
  weights.path = AnimationPath::Weights;
  clip.channels.push_back(weights);
}

// The mesh, with its blend shapes' names and its green material, in the one scene.
void add_mesh(Model& model, SurfaceMesh mesh) {
  model.materials.push_back(
      {"CactusGreen",
       R"({"name":"CactusGreen","pbrMetallicRoughness":{"baseColorFactor":[0.22,0.55,0.2,1.0],)"
       R"("metallicFactor":0.0,"roughnessFactor":0.8}})"});
  Mesh cactus_mesh;
  cactus_mesh.name = "Cactus";
  cactus_morph::describe_targets(cactus_mesh);
  Primitive primitive;
  primitive.mesh = std::move(mesh);
  primitive.material = 0;
  cactus_mesh.primitives.push_back(std::move(primitive));
  model.meshes.push_back(std::move(cactus_mesh));
  model.scenes = {{0}};
  model.default_scene = 0;
}

}  // namespace

Model make_cactus(const CactusOptions& options) {
  check_options(options);
  const double h = options.height;
  const double scale = std::sqrt(static_cast<double>(options.target_triangles) / kReferenceTriangles);
  std::vector<LimbSpec> limbs = cactus_limbs(h, scale);
  const Skeleton skeleton = cactus_skeleton(limbs, h);
  SurfaceMesh mesh = cactus_mesh(limbs, h, options.target_triangles);
  Model model;
  add_nodes_and_skin(model, skeleton);
  add_animation(model, limbs, skeleton.position.size(), options.animation_seconds);
  add_mesh(model, std::move(mesh));
  return model;
}

}  // namespace deepcut
