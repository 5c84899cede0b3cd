// SPDX-License-Identifier: MIT
// The golden corpus' operations from fixed seeds. The random numbers come from splitmix64 and
// are turned into numbers here (no std:: distributions, whose results differ between standard
// libraries); every number is written with %.6g, and the surface it was placed on is posed from
// that same text, so the command line says exactly what the tool gets.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>

#include "deepcut/core/skinning.h"
#include "deepcut/plugins/formats.h"
#include "fixtures.h"
#include "golden_corpus.h"

namespace deepcut::golden {
namespace {

class Rng {
 public:
  explicit Rng(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next() {
    std::uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double unit() { return static_cast<double>(next() >> 11) * (1.0 / 9007199254740992.0); }
  float uniform(float a, float b) { return a + static_cast<float>(unit()) * (b - a); }
  std::size_t below(std::size_t n) { return static_cast<std::size_t>(next() % n); }
  bool chance(double p) { return unit() < p; }
  glm::vec3 direction() {
    for (;;) {
      const glm::vec3 v(uniform(-1.0f, 1.0f), uniform(-1.0f, 1.0f), uniform(-1.0f, 1.0f));
      const float l = glm::length(v);
      if (l > 0.05f && l <= 1.0f) return v / l;
    }
  }

 private:
  std::uint64_t state_;
};

std::string num(float v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", static_cast<double>(v));
  return std::string(buf) == "-0" ? "0" : buf;
}
float rounded(float v) { return std::strtof(num(v).c_str(), nullptr); }
std::string list(std::initializer_list<glm::vec3> vs) {
  std::string out;
  for (const auto& v : vs)
    for (int k = 0; k < 3; ++k) out += (out.empty() ? "" : ",") + num(v[k]);
  return out;
}

// The pose an operation is placed against: the rest pose, or animation `animation` at `time`.
struct PoseChoice {
  bool posed = false;
  int animation = -1;
  float time = 0.0f;
  bool explicit_animation = false;  ///< write --animation even when it is 0
};

// The model's triangles in one pose (world space) and its size there.
struct PosedSurface {
  std::vector<std::array<glm::vec3, 3>> triangles;
  glm::vec3 center{0.0f};
  float size = 1.0f;
};

PosedSurface posed_surface(const Model& model, const PoseChoice& pose) {
  const Pose p = pose.posed && pose.animation >= 0 && !model.animations.empty()
                     ? sample_pose(model, pose.animation, pose.time)
                     : rest_pose(model);
  const auto world = world_matrices(model, p);
  PosedSurface s;
  glm::vec3 lo(1e30f), hi(-1e30f);
  for (std::size_t n = 0; n < model.nodes.size(); ++n) {
    if (model.nodes[n].mesh < 0) continue;
    for (const auto& prim : model.meshes[model.nodes[n].mesh].primitives) {
      const auto q = posed_positions(model, static_cast<int>(n), prim.mesh, world, p.weights[n]);
      prim.mesh.for_each_face([&](FaceId, const Triangle& t) {
        s.triangles.push_back({q[t[0].index], q[t[1].index], q[t[2].index]});
        for (const VertexId v : t) lo = glm::min(lo, q[v.index]), hi = glm::max(hi, q[v.index]);
      });
    }
  }
  s.center = 0.5f * (lo + hi);
  s.size = glm::length(hi - lo);
  return s;
}

struct SurfacePoint {
  glm::vec3 point{0.0f}, normal{0.0f, 0.0f, 1.0f};
};

SurfacePoint surface_point(const PosedSurface& s, Rng& rng) {
  for (int attempt = 0; attempt < 100; ++attempt) {
    const auto& t = s.triangles[rng.below(s.triangles.size())];
    const glm::vec3 n = glm::cross(t[1] - t[0], t[2] - t[0]);
    const float u = rng.uniform(0.0f, 1.0f), v = rng.uniform(0.0f, 1.0f);
    if (!(glm::length(n) > 0.0f)) continue;
    return {test::point_in_triangle(t[0], t[1], t[2], u, v), glm::normalize(n)};
  }
  return {s.center, rng.direction()};
}

// Generates the operations of one asset.
class AssetOps {
 public:
  AssetOps(std::string rel_path, std::string name, const Model& model, std::uint64_t seed)
      : path_(std::move(rel_path)), name_(std::move(name)), model_(model), rng_(seed) {}

  CorpusOp single(int index) {
    const PoseChoice pose = choose_pose();
    const PosedSurface s = posed_surface(model_, pose);
    const bool miss = rng_.chance(0.08);
    const double kind = rng_.unit();
    char id[64];
    std::snprintf(id, sizeof id, "%s-%03d", name_.c_str(), index);
    std::string args;
    std::string command;
    if (kind < 0.4) {
      command = "cut";
      args = cut_args(s, miss);
    } else if (kind < 0.7) {
      command = "tear";
      args = tear_args(s, miss);
    } else {
      command = "drill";
      args = drill_args(s, miss);
    }
    std::string line = "deepcut " + command + " " + path_ + " -o out/" + id + ".glb " + args + pose_args(pose);
    if (!rng_.chance(0.1)) line += " --json";
    return {id, line, ""};
  }

  CorpusOp apply(int index) {
    char id[64];
    std::snprintf(id, sizeof id, "%s-apply-%02d", name_.c_str(), index);
    const int count = 2 + static_cast<int>(rng_.below(4));
    std::string ops;
    for (int k = 0; k < count; ++k) {
      PoseChoice pose = choose_pose();
      // No "animation" key: the first animation (at "time", default 0), the rest pose if none.
      const bool keyless = !pose.posed && rng_.chance(0.5);
      if (keyless && !model_.animations.empty()) pose.posed = true, pose.animation = 0;
      const PosedSurface s = posed_surface(model_, pose);
      const bool miss = rng_.chance(0.05);
      const double kind = rng_.unit();
      std::string op = kind < 0.35 ? cut_json(s, miss) : kind < 0.7 ? tear_json(s, miss) : drill_json(s, miss);
      if (keyless) {
        if (pose.time != 0.0f) op += ",\"time\":" + num(pose.time);
      } else if (pose.posed) {
        op += ",\"animation\":" + std::to_string(pose.animation) + ",\"time\":" + num(pose.time);
      } else {
        op += ",\"animation\":-1";
      }
      ops += (ops.empty() ? "{" : ",{") + op + "}";
    }
    const std::string history = "{\"operations\":[" + ops + "]}";
    std::string line = "deepcut apply " + path_ + " hist/" + id + ".json -o out/" + id + ".glb";
    if (!rng_.chance(0.1)) line += " --json";
    return {id, line, history};
  }

 private:
  PoseChoice choose_pose() {
    PoseChoice p;
    if (model_.animations.empty() || !rng_.chance(0.55)) return p;
    p.posed = true;
    p.animation = static_cast<int>(rng_.below(model_.animations.size()));
    p.time = rounded(rng_.uniform(0.0f, model_.animations[p.animation].duration()));
    p.explicit_animation = rng_.chance(0.3);
    return p;
  }

  static std::string pose_args(const PoseChoice& p) {
    if (!p.posed) return "";
    std::string out = " --time " + num(p.time);
    if (p.animation != 0 || p.explicit_animation) out += " --animation " + std::to_string(p.animation);
    return out;
  }

  // A plane through a surface point with a random normal; a miss lies beyond the model.
  std::pair<glm::vec3, glm::vec3> plane(const PosedSurface& s, bool miss) {
    const SurfacePoint sp = surface_point(s, rng_);
    const glm::vec3 n = rng_.direction();
    return {miss ? s.center + 1.2f * s.size * n : sp.point, n};
  }

  // A stroke across the surface (the random sequence test's): the blade stands along the
  // normal, reaching a little above and below, and moves along a random tangent.
  std::array<glm::vec3, 4> blade(const PosedSurface& s, bool miss, float& width, bool& has_width) {
    SurfacePoint sp = surface_point(s, rng_);
    if (miss) sp.point = s.center + 2.0f * s.size * rng_.direction();
    glm::vec3 t = glm::cross(sp.normal, rng_.direction());
    t = glm::length(t) > 1e-4f ? glm::normalize(t) : glm::normalize(glm::cross(sp.normal, glm::vec3(1, 0, 0)) + 1e-3f);
    const float length = rng_.uniform(0.03f, 0.3f) * s.size;
    const glm::vec3 dir = glm::normalize(sp.normal + 0.3f * rng_.direction());
    const float above = rng_.uniform(0.005f, 0.05f) * s.size, below = rng_.uniform(0.01f, 0.1f) * s.size;
    const glm::vec3 from = sp.point - 0.5f * length * t, to = sp.point + 0.5f * length * t;
    const float w = rng_.uniform(0.0f, 1.0f);
    has_width = w >= 0.4f;
    width = w < 0.6f ? 0.0f : rng_.uniform(0.0f, 0.03f) * s.size;
    return {from + above * dir, from - below * dir, to + above * dir, to - below * dir};
  }

  // A drill through a surface point, roughly against the normal, radius 1-15% of the size
  // (log-uniform), sometimes stopping inside the model.
  std::pair<std::array<glm::vec3, 2>, float> cylinder(const PosedSurface& s, bool miss) {
    SurfacePoint sp = surface_point(s, rng_);
    if (miss) sp.point = s.center + 2.0f * s.size * rng_.direction();
    const glm::vec3 axis = glm::normalize(-sp.normal + 0.4f * rng_.direction() + 1e-4f);
    const float radius = s.size * std::exp(rng_.uniform(std::log(0.01f), std::log(0.15f)));
    const glm::vec3 a = sp.point - rng_.uniform(0.02f, 0.2f) * s.size * axis;
    const glm::vec3 b = sp.point + rng_.uniform(0.02f, 1.2f) * s.size * axis;
    return {{a, b}, radius};
  }

  int rim_edges() {
    static const int choices[] = {3, 6, 12, 32, 48};
    return rng_.chance(0.4) ? -1 : choices[rng_.below(5)];
  }

  const char* keep() {
    const double k = rng_.unit();
    return k < 0.5 ? "both" : k < 0.75 ? "positive" : "negative";
  }

  std::string cut_args(const PosedSurface& s, bool miss) {
    const auto [p, n] = plane(s, miss);
    std::string out = "--plane " + list({p, n});
    const std::string k = keep();
    if (k != "both" || rng_.chance(0.3)) out += " --keep " + k;
    if (rng_.chance(0.5)) out += " --cap";
    if (rng_.chance(0.25)) out += " --components";
    return out;
  }
  std::string tear_args(const PosedSurface& s, bool miss) {
    float width = 0.0f;
    bool has_width = false;
    const auto b = blade(s, miss, width, has_width);
    std::string out = "--blade-start " + list({b[0], b[1]}) + " --blade-end " + list({b[2], b[3]});
    if (has_width) out += " --width " + num(width);
    return out;
  }
  std::string drill_args(const PosedSurface& s, bool miss) {
    const auto [axis, radius] = cylinder(s, miss);
    std::string out = "--axis " + list({axis[0], axis[1]}) + " --radius " + num(radius);
    if (const int e = rim_edges(); e > 0) out += " --min-rim-edges " + std::to_string(e);
    if (rng_.chance(0.5)) out += " --wall";
    return out;
  }

  std::string cut_json(const PosedSurface& s, bool miss) {
    const auto [p, n] = plane(s, miss);
    const char* k = keep();
    std::string out = "\"op\":\"cut\",\"plane\":[" + list({p, n}) + "],\"keep\":\"" + k + "\"";
    out += std::string(",\"cap\":") + (rng_.chance(0.5) ? "true" : "false");
    if (rng_.chance(0.3)) out += ",\"components\":true";
    return out;
  }
  std::string tear_json(const PosedSurface& s, bool miss) {
    float width = 0.0f;
    bool has_width = false;
    const auto b = blade(s, miss, width, has_width);
    std::string out = "\"op\":\"tear\",\"blade_start\":[" + list({b[0], b[1]}) + "],\"blade_end\":[" + list({b[2], b[3]}) + "]";
    if (has_width) out += ",\"width\":" + num(width);
    return out;
  }
  std::string drill_json(const PosedSurface& s, bool miss) {
    const auto [axis, radius] = cylinder(s, miss);
    std::string out = "\"op\":\"drill\",\"axis\":[" + list({axis[0], axis[1]}) + "],\"radius\":" + num(radius);
    if (const int e = rim_edges(); e > 0) out += ",\"min_rim_edges\":" + std::to_string(e);
    if (rng_.chance(0.5)) out += ",\"wall\":true";
    return out;
  }

  std::string path_, name_;
  const Model& model_;
  Rng rng_;
};

struct AssetPlan {
  const char* path;
  const char* name;
  int singles, applies;
};

const AssetPlan kPlans[] = {
    {"assets/cactus.glb", "cactus", 55, 8},
    {"assets/models/CesiumMan/CesiumMan.glb", "cesiumman", 45, 7},
    {"assets/models/Fox/Fox.glb", "fox", 45, 7},
    {"assets/models/RiggedFigure/RiggedFigure.glb", "riggedfigure", 40, 6},
    {"assets/models/RiggedSimple/RiggedSimple.gltf", "riggedsimple", 35, 6},
    {"assets/models/SimpleSkin/SimpleSkin.gltf", "simpleskin", 25, 5},
    {"assets/models/spot/spot.obj", "spot", 40, 6},
    // Morph-target inputs (appended: the seeds of the plans above stay as they were).
    {"assets/models/AnimatedMorphCube/AnimatedMorphCube.gltf", "animatedmorphcube", 12, 2},
    {"assets/models/AnimatedMorphSphere/AnimatedMorphSphere.gltf", "animatedmorphsphere", 12, 2},
    {"assets/models/SimpleMorph/SimpleMorph.gltf", "simplemorph", 12, 2},
};

// Command lines the CLI must refuse (exit 2), and one that names a missing model.
std::vector<CorpusOp> malformed() {
  const std::string c = "assets/cactus.glb", f = "assets/models/Fox/Fox.glb";
  const std::vector<std::pair<std::string, std::string>> lines = {
      {"cut " + c + " -o out/bad-01.glb --json", ""},
      {"cut " + c + " -o out/bad-02.glb --plane 0,5,0,0,1 --json", ""},
      {"cut " + c + " -o out/bad-03.glb --plane 0,5,0,0,1,0 --keep sideways --json", ""},
      {"cut " + c + " -o out/bad-04.glb --plane 0,5,0,0,0,0 --json", ""},
      {"cut assets/no-such-model.glb -o out/bad-05.glb --plane 0,5,0,0,1,0 --json", ""},
      {"drill " + c + " -o out/bad-06.glb --axis 0,5,-3,0,5,3 --radius 0 --json", ""},
      {"drill " + c + " -o out/bad-07.glb --axis 0,5,-3,0,5,3 --radius -1 --json", ""},
      {"drill " + c + " -o out/bad-08.glb --axis 0,5,-3,0,5,3 --radius 0.2 --min-rim-edges 2 --json", ""},
      {"drill " + c + " -o out/bad-09.glb --axis 0,5,0,0,5,0 --radius 0.2 --json", ""},
      {"tear " + c + " -o out/bad-10.glb --blade-start 0,5,2,0,5,0 --json", ""},
      {"tear " + c + " -o out/bad-11.glb --blade-start 0,5,2,0,5,0 --blade-end 1,5,2,1,5,0 --width -1 --json", ""},
      {"cut " + c + " -o out/bad-12.glb --plane 0,5,0,0,1,0 --time 1 --animation 1 --json", ""},
      {"cut " + f + " -o out/bad-13.glb --plane 0,40,0,0,1,0 --time nan --json", ""},
      {"apply " + c + " hist/bad-14.json -o out/bad-14.glb --json", "{\"operations\":[{\"op\":\"slice\"}]}"},
      {"apply " + c + " hist/bad-15.json -o out/bad-15.glb --json",
       "{\"operations\":[{\"op\":\"cut\",\"plane\":[0,5,0,0,1,0],\"keep\":\"sideways\"}]}"},
      {"apply " + c + " hist/bad-16.json -o out/bad-16.glb --json", "{\"operations\":[{\"op\":\"drill\",\"axis\":[0,5,-3,0,5,3],\"radius\":0}]}"},
      {"apply " + c + " hist/bad-17.json -o out/bad-17.glb --json", "not json"},
  };
  std::vector<CorpusOp> out;
  for (std::size_t i = 0; i < lines.size(); ++i) {
    char id[32];
    std::snprintf(id, sizeof id, "bad-%02d", static_cast<int>(i + 1));
    out.push_back({id, "deepcut " + lines[i].first, lines[i].second});
  }
  return out;
}

}  // namespace

std::vector<std::string> corpus_assets() {
  std::vector<std::string> out;
  for (const auto& p : kPlans) out.emplace_back(p.path);
  return out;
}

std::vector<CorpusOp> generate_corpus(const std::string& assets_dir) {
  std::vector<CorpusOp> out;
  std::uint64_t seed = 17;
  for (const auto& plan : kPlans) {
    const std::string rel = std::string(plan.path).substr(std::string("assets/").size());
    const Model model = plugins::read_model(assets_dir + "/" + rel);
    AssetOps ops(plan.path, plan.name, model, 0x5EED0000ull + seed++);
    for (int i = 1; i <= plan.singles; ++i) out.push_back(ops.single(i));
    for (int i = 1; i <= plan.applies; ++i) out.push_back(ops.apply(i));
  }
  for (auto& op : malformed()) out.push_back(std::move(op));
  return out;
}

std::uint64_t fnv1a(const std::string& bytes) {
  std::uint64_t h = 0xcbf29ce484222325ull;
  for (const char c : bytes) {
    h ^= static_cast<unsigned char>(c);
    h *= 0x100000001b3ull;
  }
  return h;
}

}  // namespace deepcut::golden
