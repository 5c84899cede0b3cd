// SPDX-License-Identifier: MIT
// deepcut cluster / deepcut softbody: soft-body particle clustering and a headless poke demo.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "args.h"
#include "commands.h"
#include "deepcut/core/io/gltf.h"
#include "deepcut/core/posed_model.h"
#include "deepcut/core/softbody/clustering.h"
#include "deepcut/core/softbody/simulation.h"
#include "deepcut/plugins/formats.h"
#include "operation_report.h"

namespace deepcut::cli {
namespace {

using nlohmann::json;
using Clock = std::chrono::steady_clock;

double ms_since(Clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count();
}

/// One drawn primitive with triangles, at the rest pose (what rho is measured in).
struct Instance {
  const PosedMesh* rest = nullptr;  ///< its world positions in the rest pose
  const SurfaceMesh* mesh = nullptr;
};

/// The primitives of `rest` (the model at its rest pose) that have triangles, by (node, primitive).
std::vector<Instance> instances(const Model& model, const PosedModel& rest) {
  std::vector<Instance> out;
  for (const auto& [key, posed] : rest.instances()) {
    const SurfaceMesh& mesh = model.meshes[static_cast<std::size_t>(posed.mesh)].primitives[static_cast<std::size_t>(key.second)].mesh;
    if (mesh.face_count() == 0) continue;
    out.push_back({&posed, &mesh});
  }
  if (out.empty()) throw Error(ErrorCode::InvalidInput, "the model has no triangles");
  return out;
}

std::string model_path(const Args& args, const char* command) {
  if (args.positionals().size() != 1)
    throw UsageError(std::string(command) + " needs exactly one MODEL (.glb, .gltf, .obj, .ply, .stl or .off), got " +
                     std::to_string(args.positionals().size()));
  return args.positionals()[0];
}

/// Cluster options from --rho/--radius (named by `radius_option`), --particles and --cover.
/// With neither a radius nor --particles, searches for `default_particles` particles.
struct ClusterChoice {
  ClusterOptions options;
  bool searched = false;
  std::size_t target = 0;
  double search_ms = 0.0;
};

ClusterChoice choose_clusters(const Args& args, const std::vector<Instance>& inst, const char* radius_option,
                              std::size_t default_particles) {
  ClusterChoice c;
  c.options.cover_fraction = static_cast<float>(args.number("--cover", c.options.cover_fraction));
  if (!(c.options.cover_fraction > 0.0f && c.options.cover_fraction <= 1.0f))
    throw UsageError("--cover must lie in (0, 1]");
  if (args.has(radius_option) && args.has("--particles"))
    throw UsageError(std::string("give either ") + radius_option + " or --particles, not both");
  if (args.has(radius_option)) {
    c.options.radius = static_cast<float>(args.number(radius_option, 0.0));
    if (!(c.options.radius > 0.0f)) throw UsageError(std::string(radius_option) + " must be positive");
    return c;
  }
  const double target = args.number("--particles", double(default_particles));
  if (!(target >= 1.0) || target > 1e8 || target != std::floor(target))
    throw UsageError("--particles must be a whole number between 1 and 100000000");
  c.searched = true;
  c.target = static_cast<std::size_t>(target);
  std::vector<ClusterInput> inputs;
  for (const auto& i : inst) inputs.push_back({i.mesh, &i.rest->posed});
  const auto t0 = Clock::now();
  c.options.radius = radius_for_particle_count(inputs, c.target, c.options);
  c.search_ms = ms_since(t0);
  return c;
}

struct Clustered {
  std::vector<Clusters> clusters;
  ClusterStats total;
  double ms = 0.0;
};

Clustered cluster_all(const std::vector<Instance>& inst, const ClusterOptions& options) {
  Clustered out;
  std::size_t min_v = std::numeric_limits<std::size_t>::max();
  for (const auto& i : inst) {
    const auto t0 = Clock::now();
    out.clusters.push_back(Clusters::build(*i.mesh, i.rest->posed, options));
    out.ms += ms_since(t0);
    const ClusterStats s = cluster_stats(out.clusters.back(), *i.mesh);
    out.total.particles += s.particles;
    out.total.memberships += s.memberships;
    out.total.covered_vertices += s.covered_vertices;
    out.total.uncovered_vertices += s.uncovered_vertices;
    if (s.particles) min_v = std::min(min_v, s.min_vertices);
    out.total.max_vertices = std::max(out.total.max_vertices, s.max_vertices);
  }
  if (out.total.particles) {
    out.total.min_vertices = min_v;
    out.total.mean_vertices = double(out.total.memberships) / double(out.total.particles);
  }
  return out;
}

glm::vec3 to_vec3(const std::vector<double>& v) { return {float(v[0]), float(v[1]), float(v[2])}; }
json to_json(const glm::vec3& v) { return json::array({v.x, v.y, v.z}); }

// The impulse: --impulse, or --speed (model sizes per second, default 0.5) times the mass,
// pushing into the surface: against the area-weighted normal of the faces near the point.
glm::vec3 poke_impulse(const Args& args, const std::vector<Instance>& inst, const std::vector<std::vector<glm::vec3>>& posed,
                       const glm::vec3& point, float poke_radius, float size, float mass) {
  glm::vec3 impulse(0.0f);
  if (args.has("--impulse")) {
    impulse = to_vec3(args.vector("--impulse", 3));
  } else {
    glm::vec3 normal(0.0f);
    const float r2 = poke_radius * poke_radius;
    for (std::size_t k = 0; k < inst.size(); ++k)
      inst[k].mesh->for_each_face([&](FaceId, const Triangle& t) {
        const glm::vec3 &a = posed[k][t[0].index], &b = posed[k][t[1].index], &cc = posed[k][t[2].index];
        const glm::vec3 centroid = (a + b + cc) / 3.0f;
        if (glm::dot(centroid - point, centroid - point) <= r2) normal += glm::cross(b - a, cc - a);
      });
    if (glm::length(normal) == 0.0f)
      throw Error(ErrorCode::InvalidArgument,
                  "softbody: no surface within --radius " + std::to_string(poke_radius) +
                      " of the poke point; move it onto the model or pass --impulse");
    const double speed = args.number("--speed", 0.5);
    if (!(speed > 0.0)) throw UsageError("--speed must be positive");
    impulse = -glm::normalize(normal) * float(speed) * size * mass;
  }
  if (!std::isfinite(impulse.x) || !std::isfinite(impulse.y) || !std::isfinite(impulse.z))
    throw UsageError("the impulse overflows single precision; use a smaller --speed or --impulse");
  return impulse;
}

OptionSpec cover_option() {
  return {"--cover", "F",
          "seeds are placed until every vertex lies within F * RHO of a seed, in (0, 1]: below 1 the particles "
          "overlap, so the weights blend smoothly",
          number_text(ClusterOptions().cover_fraction), false, false};
}

}  // namespace

const CommandSpec& cluster_command() {
  static const CommandSpec spec = with_synopsis(
      {"cluster",
       {{"MODEL", "the model to cluster: a rigged .glb/.gltf, or a static .obj/.ply/.stl/.off mesh"}},
       "soft-body particles of radius RHO (rest pose): counts, timing",
       "Groups the vertices into soft-body particles at the rest pose: seeds by farthest-point sampling "
       "(see --cover), each particle holds the vertices within RHO of its seed (a vertex may be in several, "
       "weighted (1 - (d/RHO)^2)^2, normalised), and a particle whose ball reaches two separate surface "
       "sheets is split into its connected parts. Prints the particle count, vertices per particle and "
       "the clustering time; writes nothing.",
       {{"--radius", "RHO", "particle radius in model units (rest pose); give it or --particles", "", true, true},
        {"--particles", "N", "search the radius that gives about N particles", "", false, false},
        cover_option(),
        json_option("radius, cover_fraction, primitives, particles, min_vertices, mean_vertices, "
                    "max_vertices, memberships, covered_vertices, uncovered_vertices and ms (with "
                    "--particles also target_particles and search_ms)")},
       "deepcut cluster assets/cactus.glb --particles 224",
       {}});
  return spec;
}

int run_cluster(const std::vector<std::string>& argv) {
  const Args args(argv, cluster_command());
  const std::string path = model_path(args, "cluster");
  if (!args.has("--radius") && !args.has("--particles"))
    throw UsageError("cluster needs --radius RHO (rest-pose model units) or --particles N");
  const Model model = plugins::read_model(path);
  print_problems(std::cerr, path, model.import_problems);
  const PosedModel rest = PosedModel::build(model, -1, 0.0f, PoseDetail::Positions);
  const auto inst = instances(model, rest);
  const ClusterChoice choice = choose_clusters(args, inst, "--radius", 0);
  const Clustered c = cluster_all(inst, choice.options);
  const ClusterStats& s = c.total;
  if (args.flag("--json")) {
    json out = {{"file", path},
                {"radius", choice.options.radius},
                {"cover_fraction", choice.options.cover_fraction},
                {"primitives", inst.size()},
                {"particles", s.particles},
                {"min_vertices", s.min_vertices},
                {"mean_vertices", s.mean_vertices},
                {"max_vertices", s.max_vertices},
                {"memberships", s.memberships},
                {"covered_vertices", s.covered_vertices},
                {"uncovered_vertices", s.uncovered_vertices},
                {"problems", problems_report(model.import_problems)},
                {"ms", c.ms}};
    if (choice.searched) {
      out["target_particles"] = choice.target;
      out["search_ms"] = choice.search_ms;
    }
    std::cout << out.dump(2) << "\n";
    return 0;
  }
  std::cout << path << "\n";
  if (choice.searched)
    std::cout << "  radius for ~" << choice.target << " particles: ";
  else
    std::cout << "  radius: ";
  std::cout << choice.options.radius << " (cover fraction " << choice.options.cover_fraction << ")\n"
            << "  particles " << s.particles << ", vertices per particle min " << s.min_vertices << " / mean "
            << std::fixed << std::setprecision(1) << s.mean_vertices << " / max " << s.max_vertices << "\n"
            << "  vertices covered " << s.covered_vertices << ", uncovered " << s.uncovered_vertices
            << ", memberships " << s.memberships << "\n"
            << "  clustering " << std::setprecision(2) << c.ms << " ms";
  if (choice.searched) std::cout << " (radius search " << choice.search_ms << " ms)";
  std::cout << "\n";
  return 0;
}

const CommandSpec& softbody_command() {
  const SoftBodyOptions sim{};
  static const CommandSpec spec = with_synopsis(
      {"softbody",
       {{"MODEL", "the model to poke: a rigged .glb/.gltf, or a static .obj/.ply/.stl/.off mesh"}},
       "poke the soft body, step N frames, report max displacement",
       "The headless poke demo: clusters the model into particles (--rho or --particles), pokes the "
       "particles whose centre lies within --radius of the point with an impulse, steps --frames frames of "
       "--dt seconds and prints the largest vertex displacement per frame: it rises, then decays to about "
       "0 (each particle is a damped spring, integrated exactly, so any step is stable). Writes nothing.",
       {{"--poke", "X,Y,Z", "the point poked, world space at the pose of --time (the rest pose without --time)",
         "", true, false},
        {"--radius", "R", "particles whose centre lies within R model units of the point are pushed",
         "1.5 * RHO", false, false},
        {"--impulse", "IX,IY,IZ", "the impulse given to each poked particle (mass times velocity, model units)",
         "", false, true},
        {"--speed", "S",
         "the default impulse's speed, in model sizes (bounding-box diagonals) per second, into the surface "
         "(against the normal of the faces near the point)",
         "0.5", false, false},
        {"--frames", "N", "frames to step (1 to 100000)", "60", false, false},
        {"--dt", "DT", "seconds per frame, in (0, 1]", "1/30", false, false},
        {"--rho", "RHO", "particle radius in model units (rest pose)", "", false, true},
        {"--particles", "N", "search the particle radius that gives about N particles", "224", false, false},
        cover_option(),
        {"--stiffness", "K", "spring stiffness of every particle (force per model unit of displacement)",
         number_text(sim.stiffness), false, false},
        {"--damping", "C", "damping of every particle (force per unit velocity; the default is critical for "
                           "the default stiffness and mass)",
         number_text(sim.damping), false, false},
        {"--mass", "M", "mass of every particle", number_text(sim.mass), false, false},
        pose_options()[0],
        pose_options()[1],
        {"--animate", "", "play the animation while stepping, from --time: the displacement is added to the "
                          "skinned positions of the current pose", "", false, false},
        json_option("max_displacement (one per frame), peak, peak_frame, final, final_relative, particles, "
                    "particles_reached and step_ms")},
       "deepcut softbody assets/cactus.glb --poke 0.6,5,0 --frames 90 --json",
       {}});
  return spec;
}

namespace {

/// What softbody steps: the point poked, the frames and their length, the springs.
struct StepOptions {
  glm::vec3 point{0.0f};
  int frames = 60;
  float dt = 1.0f / 30.0f;
  SoftBodyOptions sim;
};

StepOptions step_options(const Args& args) {
  if (!args.has("--poke"))
    throw UsageError("softbody needs --poke X,Y,Z (world space of the pose at --time)");
  StepOptions o;
  o.point = to_vec3(args.vector("--poke", 3));
  const double frames_d = args.number("--frames", 60);
  if (!(frames_d >= 1 && frames_d <= 100000) || frames_d != std::floor(frames_d))
    throw UsageError("--frames must be a whole number between 1 and 100000");
  o.frames = static_cast<int>(frames_d);
  o.dt = static_cast<float>(args.number("--dt", 1.0 / 30.0));
  if (!(o.dt > 0.0f && o.dt <= 1.0f)) throw UsageError("--dt must lie in (0, 1] seconds");
  o.sim.stiffness = static_cast<float>(args.number("--stiffness", o.sim.stiffness));
  o.sim.damping = static_cast<float>(args.number("--damping", o.sim.damping));
  o.sim.mass = static_cast<float>(args.number("--mass", o.sim.mass));
  return o;
}

/// The pose softbody plays (--animation, --time, --animate) and the model's problems with those
/// of the pose after them (the pose's printed to stderr here).
struct PlayedPose {
  int animation = -1;  ///< -1: the rest pose
  bool animate = false;
  float start = 0.0f;
  std::vector<ImportProblem> problems;
};

PlayedPose played_pose(const Args& args, const Model& model, const std::string& path) {
  PlayedPose p;
  p.animation = animation_option(args, model.animations.size());
  p.animate = args.flag("--animate");
  if (p.animate && model.animations.empty()) throw UsageError("--animate: the model has no animation");
  if (p.animate && p.animation < 0)
    throw UsageError("--animate needs an animation to play; --animation -1 is the rest pose");
  if (!p.animate && !args.has("--time")) p.animation = -1;
  p.start = static_cast<float>(args.number("--time", 0.0));
  const std::vector<ImportProblem> pose = pose_problems(args, model);
  print_problems(std::cerr, path, pose);
  p.problems = model.import_problems;
  p.problems.insert(p.problems.end(), pose.begin(), pose.end());
  return p;
}

/// The posed positions of every instance at a time of one animation (-1: the rest pose).
class InstancePoser {
 public:
  InstancePoser(const Model& model, const std::vector<Instance>& inst, int animation)
      : model_(model), inst_(inst), animation_(animation) {}
  std::vector<std::vector<glm::vec3>> operator()(float t) {
    at_time_.repose(model_, animation_, t);
    std::vector<std::vector<glm::vec3>> out;
    for (const auto& i : inst_) out.push_back(at_time_.find(i.rest->node, i.rest->primitive)->posed);
    return out;
  }

 private:
  const Model& model_;
  const std::vector<Instance>& inst_;
  int animation_;
  PosedModel at_time_;
};

/// The diagonal of the bounding box of the points the instances' faces use.
float drawn_diagonal(const std::vector<Instance>& inst, const std::vector<std::vector<glm::vec3>>& posed) {
  BoundingBox box;
  for (std::size_t k = 0; k < inst.size(); ++k)
    inst[k].mesh->for_each_face([&](FaceId, const Triangle& t) {
      for (const VertexId v : t) box.add(posed[k][v.index]);
    });
  return box.diagonal();
}

/// One soft body per instance (into `states`), each poked at `point`. @returns how many particles
/// the poke reached. @throws Error when it reaches none.
std::size_t poke_all(const Clustered& c, const std::vector<std::vector<glm::vec3>>& posed,
                     const StepOptions& o, const glm::vec3& impulse, float poke_radius,
                     std::vector<SoftBodyState>& states) {
  std::size_t reached = 0;
  for (std::size_t k = 0; k < c.clusters.size(); ++k) {
    states.push_back(make_soft_body(c.clusters[k]));
    reached += poke(states[k], c.clusters[k], posed[k], o.point, impulse, poke_radius, o.sim);
  }
  if (reached == 0)
    throw Error(ErrorCode::InvalidArgument, "softbody: the poke at (" + std::to_string(o.point.x) + ", " +
                                                std::to_string(o.point.y) + ", " + std::to_string(o.point.z) +
                                                ") with radius " + std::to_string(poke_radius) +
                                                " reaches no particle");
  return reached;
}

/// Throws when a frame's displacement left float range (an impulse this large: the input's fault).
void check_finite(float max_displacement, const std::vector<glm::vec3>& deformed, int frame) {
  const bool overflow = !std::isfinite(max_displacement) ||
                        std::any_of(deformed.begin(), deformed.end(), [](const glm::vec3& p) {
                          return !std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z);
                        });
  if (overflow)
    throw Error(ErrorCode::InvalidArgument, "the displacement overflows at frame " + std::to_string(frame) +
                                                "; use a smaller --speed or --impulse");
}

/// The frames stepped: the largest vertex displacement of each, and the time the steps took.
struct Stepped {
  std::vector<double> max_displacement;
  double step_ms = 0.0;
};

/// Steps every soft body frame by frame: springs, then the vertices (skinned pose + displacement),
/// as the studio does per frame; the pose moves on with the animation when `play.animate`.
Stepped step_frames(const StepOptions& o, const PlayedPose& play, InstancePoser& pose_at,
                    std::vector<std::vector<glm::vec3>> posed, const Clustered& c,
                    std::vector<SoftBodyState>& states) {
  Stepped out;
  std::vector<glm::vec3> deformed;
  float t = play.start;
  for (int f = 0; f < o.frames; ++f) {
    if (play.animate) {
      t += o.dt;
      posed = pose_at(t);
    }
    const auto t0 = Clock::now();
    float m = 0.0f;
    for (std::size_t k = 0; k < states.size(); ++k) {
      step_soft_body(states[k], o.dt, o.sim);
      m = std::max(m, deformed_positions(states[k], c.clusters[k], posed[k], deformed));
      check_finite(m, deformed, f);
    }
    out.step_ms += ms_since(t0);
    out.max_displacement.push_back(m);
  }
  return out;
}

/// What softbody reports.
struct PokeReport {
  std::string path;
  float rho = 0.0f;
  std::size_t particles = 0;
  double cluster_ms = 0.0;
  glm::vec3 point{0.0f}, impulse{0.0f};
  float poke_radius = 0.0f;
  std::size_t reached = 0;
  int frames = 0;
  float dt = 0.0f;
  bool animated = false;
  float size = 0.0f;  ///< the model's size (its drawn bounding box's diagonal)
  Stepped stepped;
  std::vector<ImportProblem> problems;
};

void print_json(const PokeReport& r) {
  const std::vector<double>& max_disp = r.stepped.max_displacement;
  const auto peak = std::max_element(max_disp.begin(), max_disp.end());
  const std::size_t peak_frame = static_cast<std::size_t>(peak - max_disp.begin());
  std::cout
      << json{{"file", r.path},
              {"rho", r.rho},
              {"particles", r.particles},
              {"cluster_ms", r.cluster_ms},
              {"poke",
               {{"point", to_json(r.point)}, {"radius", r.poke_radius}, {"impulse", to_json(r.impulse)}}},
              {"particles_reached", r.reached},
              {"frames", r.frames},
              {"dt", r.dt},
              {"animated", r.animated},
              {"model_size", r.size},
              {"max_displacement", max_disp},
              {"peak", *peak},
              {"peak_frame", peak_frame},
              {"final", max_disp.back()},
              {"final_relative", r.size > 0.0f ? max_disp.back() / r.size : 0.0},
              {"problems", problems_report(r.problems)},
              {"step_ms", r.stepped.step_ms / r.frames}}
             .dump(2)
      << "\n";
}

void print_text(const PokeReport& r) {
  const std::vector<double>& max_disp = r.stepped.max_displacement;
  const auto peak = std::max_element(max_disp.begin(), max_disp.end());
  const std::size_t peak_frame = static_cast<std::size_t>(peak - max_disp.begin());
  std::cout << r.path << "\n"
            << "  particles " << r.particles << " (rho " << r.rho << "), poke reached " << r.reached << "\n"
            << "  max displacement: peak " << *peak << " at frame " << peak_frame << ", final "
            << max_disp.back() << " (" << (r.size > 0.0f ? max_disp.back() / r.size : 0.0)
            << " of the model size) after " << r.frames << " frames of " << r.dt << " s\n"
            << "  step + vertex update " << std::fixed << std::setprecision(4) << r.stepped.step_ms / r.frames
            << " ms per frame\n";
  for (int f = 0; f < r.frames; ++f)
    std::cout << "    frame " << std::setw(4) << f << "  " << std::scientific << std::setprecision(3)
              << max_disp[static_cast<std::size_t>(f)] << std::fixed << "\n";
}

}  // namespace

int run_softbody(const std::vector<std::string>& argv) {
  const Args args(argv, softbody_command());
  PokeReport r;
  r.path = model_path(args, "softbody");
  const StepOptions o = step_options(args);
  const Model model = plugins::read_model(r.path);
  print_problems(std::cerr, r.path, model.import_problems);
  PlayedPose play = played_pose(args, model, r.path);

  const PosedModel rest = PosedModel::build(model, -1, 0.0f, PoseDetail::Positions);
  const auto inst = instances(model, rest);
  const ClusterChoice choice = choose_clusters(args, inst, "--rho", 224);
  const Clustered c = cluster_all(inst, choice.options);
  r.poke_radius = static_cast<float>(args.number("--radius", 1.5 * choice.options.radius));
  if (!(r.poke_radius > 0.0f)) throw UsageError("--radius must be positive");

  InstancePoser pose_at(model, inst, play.animation);
  std::vector<std::vector<glm::vec3>> posed = pose_at(play.start);
  r.size = drawn_diagonal(inst, posed);
  r.impulse = poke_impulse(args, inst, posed, o.point, r.poke_radius, r.size, o.sim.mass);
  std::vector<SoftBodyState> states;
  r.reached = poke_all(c, posed, o, r.impulse, r.poke_radius, states);
  r.stepped = step_frames(o, play, pose_at, std::move(posed), c, states);

  r.rho = choice.options.radius;
  r.particles = c.total.particles;
  r.cluster_ms = c.ms;
  r.point = o.point;
  r.frames = o.frames;
  r.dt = o.dt;
  r.animated = play.animate;
  r.problems = std::move(play.problems);
  if (args.flag("--json"))
    print_json(r);
  else
    print_text(r);
  return 0;
}

}  // namespace deepcut::cli
