// SPDX-License-Identifier: MIT
// glTF import: nodes, skins, animations, images and the objects carried through untouched.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <set>
#include <utility>

#include "io/gltf_reader.h"

namespace deepcut::gltf_detail {
namespace {

using nlohmann::json;

// Largest image side accepted (GPUs cap textures at 16384 or 32768 pixels a side).
constexpr std::uint32_t kMaxImageSide = 32768;

std::string sniff_mime(const std::vector<unsigned char>& d) {
  if (d.size() >= 8 && d[0] == 0x89 && d[1] == 'P' && d[2] == 'N' && d[3] == 'G') return "image/png";
  if (d.size() >= 3 && d[0] == 0xFF && d[1] == 0xD8 && d[2] == 0xFF) return "image/jpeg";
  if (d.size() >= 12 && std::memcmp(d.data(), "RIFF", 4) == 0 && std::memcmp(d.data() + 8, "WEBP", 4) == 0) return "image/webp";
  if (d.size() >= 4 && std::memcmp(d.data(), "\xABKTX", 4) == 0) return "image/ktx2";
  return "";
}

// Width and height that a PNG or JPEG header claims ({0, 0} when unknown). Reads headers only.
std::pair<std::uint32_t, std::uint32_t> image_dimensions(const std::vector<unsigned char>& d) {
  auto be16 = [&](std::size_t at) { return std::uint32_t(d[at]) << 8 | d[at + 1]; };
  auto be32 = [&](std::size_t at) { return be16(at) << 16 | be16(at + 2); };
  if (d.size() >= 24 && d[0] == 0x89 && d[1] == 'P' && std::memcmp(d.data() + 12, "IHDR", 4) == 0) return {be32(16), be32(20)};
  if (d.size() >= 4 && d[0] == 0xFF && d[1] == 0xD8) {
    std::size_t at = 2;
    while (at + 9 < d.size() && d[at] == 0xFF) {
      const unsigned char marker = d[at + 1];
      const bool sof = marker >= 0xC0 && marker <= 0xCF && marker != 0xC4 && marker != 0xC8 && marker != 0xCC;
      if (sof) return {be16(at + 7), be16(at + 5)};
      at += 2 + be16(at + 2);
    }
  }
  return {0, 0};
}

// Node `g`'s transform (matrix, translation, rotation, scale, as the file gives them) into `n`.
void read_transform(const tinygltf::Node& g, Node& n) {
  if (g.matrix.size() == 16) {
    glm::mat4 m;
    for (int k = 0; k < 16; ++k) m[k / 4][k % 4] = static_cast<float>(g.matrix[k]);
    n.matrix = m;
  }
  if (g.translation.size() == 3)
    n.translation = glm::vec3(g.translation[0], g.translation[1], g.translation[2]);
  if (g.rotation.size() == 4)
    n.rotation = glm::quat(static_cast<float>(g.rotation[3]), static_cast<float>(g.rotation[0]),
                           static_cast<float>(g.rotation[1]), static_cast<float>(g.rotation[2]));
  if (g.scale.size() == 3) n.scale = glm::vec3(g.scale[0], g.scale[1], g.scale[2]);
}

bool finite_transform(const Node& n) {
  bool finite = true;
  if (n.matrix)
    for (int k = 0; k < 16; ++k) finite = finite && std::isfinite((*n.matrix)[k / 4][k % 4]);
  for (int k = 0; k < 3; ++k) finite = finite && std::isfinite(n.translation[k]) && std::isfinite(n.scale[k]);
  for (int k = 0; k < 4; ++k) finite = finite && std::isfinite(n.rotation[k]);
  return finite;
}

// How messages name channel `c` of animation `a`.
std::string channel_name(std::size_t a, std::size_t c) {
  return "animation " + std::to_string(a) + " channel " + std::to_string(c);
}

// The animated property a channel's target path names; none for an unknown path.
std::optional<AnimationPath> path_named(const std::string& path) {
  if (path == "translation") return AnimationPath::Translation;
  if (path == "rotation") return AnimationPath::Rotation;
  if (path == "scale") return AnimationPath::Scale;
  if (path == "weights") return AnimationPath::Weights;
  return std::nullopt;
}

// A sampler's interpolation by its glTF name (linear unless STEP or CUBICSPLINE).
Interpolation interpolation_named(const std::string& name) {
  if (name == "STEP") return Interpolation::Step;
  if (name == "CUBICSPLINE") return Interpolation::CubicSpline;
  return Interpolation::Linear;
}

// Rotations must be unit quaternions (glTF; the validator checks it): normalises the key values
// of rotation sampler `s` (for cubic splines only the values, not the tangents), a zero one to the
// identity. Float noise (SimpleSkin's 0.707s are 1.5e-4 short) is fixed silently: returns how many
// were further off than that.
std::size_t normalise_rotations(AnimationSampler& s) {
  const std::size_t per_key = s.interpolation == Interpolation::CubicSpline ? 3 : 1;
  std::size_t fixed = 0;
  for (std::size_t k = 0; k < s.input.size(); ++k) {
    float* q = &s.output[4 * (k * per_key + (per_key == 3 ? 1 : 0))];
    const double len =
        std::sqrt(double(q[0]) * q[0] + double(q[1]) * q[1] + double(q[2]) * q[2] + double(q[3]) * q[3]);
    if (std::abs(len - 1.0) <= 1e-6) continue;
    fixed += std::abs(len - 1.0) > 1e-3;
    if (len < 1e-12 || !std::isfinite(len)) {
      q[0] = q[1] = q[2] = 0.0f;
      q[3] = 1.0f;
    } else {
      for (int i = 0; i < 4; ++i) q[i] = static_cast<float>(q[i] / len);
    }
  }
  return fixed;
}

}  // namespace

void Reader::read_nodes() {
  for (std::size_t i = 0; i < gltf_.nodes.size(); ++i) model_.nodes.push_back(read_node(i));
  check_hierarchy();
  read_scenes();
}

Node Reader::read_node(std::size_t i) {
  static const json empty = json::object();
  const auto& g = gltf_.nodes[i];
  const json& r = raw_.contains("nodes") && raw_["nodes"].is_array() && i < raw_["nodes"].size()
                      ? raw_["nodes"][i]
                      : empty;
  Node n;
  n.name = g.name;
  for (int c : g.children) {
    if (c < 0 || static_cast<std::size_t>(c) >= gltf_.nodes.size())
      fail("node " + std::to_string(i) + " has child " + std::to_string(c) + ", which does not exist");
    n.children.push_back(c);
  }
  read_transform(g, n);
  if (!finite_transform(n))
    fail("node " + std::to_string(i) + ": its transform is not finite (a value overflows a 32-bit float)");
  auto check = [&](int idx, std::size_t size, const char* kind) {
    if (idx >= 0 && static_cast<std::size_t>(idx) >= size)
      fail("node " + std::to_string(i) + " refers to " + kind + " " + std::to_string(idx) +
           ", which does not exist");
    return idx;
  };
  n.mesh = check(g.mesh, gltf_.meshes.size(), "mesh");
  n.skin = check(g.skin, gltf_.skins.size(), "skin");
  n.camera = check(g.camera, gltf_.cameras.size(), "camera");
  n.extras_json = dump_member(r, "extras");
  n.extensions_json = dump_member(r, "extensions");
  for (const double w : g.weights) {
    if (!std::isfinite(static_cast<float>(w)))
      fail("node " + std::to_string(i) + ": a morph weight is not finite (a value overflows a 32-bit float)");
    n.weights.push_back(static_cast<float>(w));
  }
  return n;
}

// Cycles or a node with two parents would make the hierarchy ill-defined.
void Reader::check_hierarchy() const {
  std::vector<int> parent(model_.nodes.size(), -1);
  for (std::size_t i = 0; i < model_.nodes.size(); ++i)
    for (int c : model_.nodes[i].children) {
      if (parent[c] >= 0 || c == static_cast<int>(i)) fail("node " + std::to_string(c) + " has more than one parent");
      parent[c] = static_cast<int>(i);
    }
  for (std::size_t i = 0; i < parent.size(); ++i) {
    std::size_t steps = 0;
    for (int x = parent[i]; x >= 0; x = parent[x])
      if (++steps > parent.size()) fail("the node hierarchy has a cycle through node " + std::to_string(i));
  }
}

// The scenes' root nodes, and the default scene (one scene of every root when the file has none).
void Reader::read_scenes() {
  for (const auto& s : gltf_.scenes) {
    std::vector<int> roots;
    for (int n : s.nodes) {
      if (n < 0 || static_cast<std::size_t>(n) >= gltf_.nodes.size()) fail("a scene refers to node " + std::to_string(n) + ", which does not exist");
      roots.push_back(n);
    }
    model_.scenes.push_back(std::move(roots));
  }
  model_.default_scene = gltf_.defaultScene >= 0 ? gltf_.defaultScene : 0;
  if (model_.scenes.empty()) {
    model_.scenes.push_back(model_.root_nodes());
    model_.default_scene = 0;
  }
}

void Reader::read_skins() {
  for (std::size_t i = 0; i < gltf_.skins.size(); ++i) {
    const auto& g = gltf_.skins[i];
    Skin s;
    s.name = g.name;
    for (int j : g.joints) {
      if (j < 0 || static_cast<std::size_t>(j) >= model_.nodes.size())
        fail("skin " + std::to_string(i) + " names joint node " + std::to_string(j) + ", which does not exist");
      s.joints.push_back(j);
    }
    if (s.joints.empty()) fail("skin " + std::to_string(i) + " has no joints");
    if (g.skeleton >= 0 && static_cast<std::size_t>(g.skeleton) < model_.nodes.size()) s.skeleton = g.skeleton;
    if (g.inverseBindMatrices >= 0) {
      int comps = 0;
      const auto m = read_floats(g.inverseBindMatrices, "skin inverseBindMatrices", &comps);
      if (comps != 16) fail("skin " + std::to_string(i) + ": inverseBindMatrices are not MAT4");
      if (m.size() / 16 < s.joints.size()) fail("skin " + std::to_string(i) + ": fewer inverseBindMatrices than joints");
      for (std::size_t j = 0; j < s.joints.size(); ++j) {
        glm::mat4 mat;
        for (int k = 0; k < 16; ++k) mat[k / 4][k % 4] = m[16 * j + static_cast<std::size_t>(k)];
        for (int k = 0; k < 16; ++k)
          if (!std::isfinite(mat[k / 4][k % 4]))
            fail("skin " + std::to_string(i) + ": inverse bind matrix " + std::to_string(j) + " is not finite (NaN or Inf)");
        s.inverse_bind_matrices.push_back(mat);
      }
    } else {
      s.had_inverse_bind_matrices = false;
      s.inverse_bind_matrices.assign(s.joints.size(), glm::mat4(1.0f));
      problem("skin-no-inverse-bind-matrices", 1,
              {"skin has no inverseBindMatrices (identity matrices used, written explicitly on export)",
               "skins have no inverseBindMatrices (identity matrices used, written explicitly on export)"},
              "skin " + std::to_string(i));
    }
    repair_skin(i, s);
    model_.skins.push_back(std::move(s));
  }
}

void Reader::read_animations() {
  for (std::size_t a = 0; a < gltf_.animations.size(); ++a) model_.animations.push_back(read_animation(a));
}

Animation Reader::read_animation(std::size_t a) {
  const auto& g = gltf_.animations[a];
  Animation anim;
  anim.name = g.name;
  std::vector<int> sampler_map(g.samplers.size(), -1);  // the file's sampler -> anim.samplers' (-1: not read)
  for (std::size_t c = 0; c < g.channels.size(); ++c) {
    const auto& ch = g.channels[c];
    if (ch.sampler < 0 || static_cast<std::size_t>(ch.sampler) >= g.samplers.size())
      fail(channel_name(a, c) + " refers to a missing sampler");
    if (ch.target_node < 0) continue;  // targets defined by extensions are not animated here
    if (static_cast<std::size_t>(ch.target_node) >= model_.nodes.size())
      fail(channel_name(a, c) + " targets a missing node");
    AnimationChannel out;
    out.node = ch.target_node;
    const std::optional<AnimationPath> path = path_named(ch.target_path);
    if (!path) fail(channel_name(a, c) + ": unknown path '" + ch.target_path + "'");
    out.path = *path;
    if (sampler_map[ch.sampler] < 0) {
      std::optional<AnimationSampler> s = read_sampler(g.samplers[ch.sampler], out.path, a, c);
      if (!s) continue;  // a morph weight channel dropped (fit_weights_sampler says why)
      sampler_map[ch.sampler] = static_cast<int>(anim.samplers.size());
      anim.samplers.push_back(std::move(*s));
    }
    out.sampler = sampler_map[ch.sampler];
    // (weight channels are checked against the node's mesh in resolve_morph_weights)
    if (out.path != AnimationPath::Weights)
      check_transform_sampler(anim.samplers[out.sampler], ch.target_path, a, c);
    anim.channels.push_back(out);
  }
  return anim;
}

// Sampler `gs` of animation `a`, first read for channel `c` of path `path`; none when it drives
// morph weights that fit_weights_sampler drops.
std::optional<AnimationSampler> Reader::read_sampler(const tinygltf::AnimationSampler& gs, AnimationPath path,
                                                     std::size_t a, std::size_t c) {
  auto where = [&] { return "animation " + std::to_string(a); };  // (built on failure only)
  AnimationSampler s;
  int in_comps = 0, out_comps = 0;
  const Floats input = read_floats(gs.input, "animation sampler input", &in_comps);
  const Floats output = read_floats(gs.output, "animation sampler output", &out_comps);
  s.input.assign(input.begin(), input.end());
  s.output.assign(output.begin(), output.end());
  if (in_comps != 1) fail(where() + ": sampler input is not SCALAR");
  for (std::size_t k = 0; k < s.input.size(); ++k) {
    if (!std::isfinite(s.input[k])) fail(where() + ": key time is not finite");
    if (k && s.input[k] < s.input[k - 1]) fail(where() + ": key times are not increasing");
  }
  s.components = out_comps;
  s.interpolation = interpolation_named(gs.interpolation);
  const std::size_t per_key = s.interpolation == Interpolation::CubicSpline ? 3 : 1;
  if (path == AnimationPath::Weights) {
    if (!fit_weights_sampler(s, gltf_.accessors[gs.output].type, a, c)) return std::nullopt;
  } else if (s.output.size() != s.input.size() * per_key * std::size_t(out_comps)) {
    fail(where() + ": sampler output count does not match its input count");
  }
  for (const float v : s.output)
    if (!std::isfinite(v)) fail(where() + ": a sampler output value is not finite (NaN or Inf)");
  return s;
}

// A translation, rotation or scale channel's sampler (channel `c` of animation `a`, driving
// `path`): its values have the path's type, and rotations are unit quaternions.
void Reader::check_transform_sampler(AnimationSampler& s, const std::string& path, std::size_t a,
                                     std::size_t c) {
  const bool rotation = path == "rotation";
  if (s.components != (rotation ? 4 : 3))
    fail(channel_name(a, c) + ": output has the wrong type for " + path);
  if (!rotation) return;
  const std::size_t fixed = normalise_rotations(s);
  if (fixed)
    problem("rotations-normalised", fixed,
            {"rotation was not a unit quaternion (normalised)",
             "rotations were not unit quaternions (normalised)"},
            channel_name(a, c));
}

void Reader::read_images() {
  for (std::size_t i = 0; i < gltf_.images.size(); ++i) {
    const auto& g = gltf_.images[i];
    Image img;
    img.name = g.name;
    if (g.bufferView >= 0) {
      const auto& bv = gltf_.bufferViews.at(g.bufferView);
      const unsigned char* base = view_bytes(g.bufferView, 0, 1, 1, bv.byteLength, "image " + std::to_string(i));
      img.data.assign(base, base + bv.byteLength);
    } else {
      img.data = g.image;
    }
    // Images are carried through undecoded, but whoever displays the model will decode them: a
    // header claiming more than any GPU texture can hold is a decompression bomb, not a texture.
    const auto [width, height] = image_dimensions(img.data);
    if (width > kMaxImageSide || height > kMaxImageSide)
      fail("image " + std::to_string(i) + " claims " + std::to_string(width) + " x " + std::to_string(height) +
           " pixels, over the " + std::to_string(kMaxImageSide) + "-pixel limit per side");
    img.mime_type = g.mimeType.empty() ? sniff_mime(img.data) : g.mimeType;
    if (img.mime_type.empty()) img.mime_type = "image/png";
    model_.images.push_back(std::move(img));
  }
}

void Reader::read_passthrough() {
  auto take = [&](const char* key, std::vector<PassthroughObject>& out) {
    if (!raw_.contains(key) || !raw_[key].is_array()) return;
    for (const auto& o : raw_[key]) {
      if (!o.is_object()) fail(std::string("'") + key + "' holds something that is not an object");
      out.push_back({o.value("name", ""), o.dump()});
    }
  };
  take("materials", model_.materials);
  take("textures", model_.textures);
  take("samplers", model_.samplers);
  take("cameras", model_.cameras);
  for (const auto& t : raw_.value("textures", json::array())) {
    const int src = t.value("source", -1);
    if (src >= 0 && static_cast<std::size_t>(src) >= gltf_.images.size())
      fail("a texture refers to image " + std::to_string(src) + ", which does not exist");
    const int smp = t.value("sampler", -1);
    if (smp >= 0 && static_cast<std::size_t>(smp) >= model_.samplers.size())
      fail("a texture refers to sampler " + std::to_string(smp) + ", which does not exist");
  }
  for (const char* key : {"extensionsUsed", "extensionsRequired"}) {
    if (!raw_.contains(key) || !raw_[key].is_array()) continue;
    auto& out = std::string(key) == "extensionsUsed" ? model_.extensions_used : model_.extensions_required;
    for (const auto& e : raw_[key])
      if (e.is_string()) out.push_back(e.get<std::string>());
  }
  model_.extras_json = dump_member(raw_, "extras");
  model_.extensions_json = dump_member(raw_, "extensions");
  model_.asset_copyright = raw_["asset"].value("copyright", "");
  model_.asset_extras_json = dump_member(raw_["asset"], "extras");
}

}  // namespace deepcut::gltf_detail

namespace deepcut::gltf_detail {
namespace {

// Inverse bind matrices whose last row is this close to (0, 0, 0, 1) are float noise of an
// affine matrix and are snapped to it (the validator's ACCESSOR_INVALID_IBM wants it exact);
// farther off, the matrix is not an inverse bind matrix glTF allows and the file is refused.
constexpr float kIbmLastRowTolerance = 1e-3f;

// Adds the name of every extension used anywhere inside `o` to `names`.
void collect_extension_names(const json& o, std::set<std::string>& names) {
  if (o.is_array()) {
    for (const auto& item : o) collect_extension_names(item, names);
  } else if (o.is_object()) {
    for (const auto& item : o.items()) {
      if (item.key() == "extensions" && item.value().is_object())
        for (const auto& e : item.value().items()) names.insert(e.key());
      collect_extension_names(item.value(), names);
    }
  }
}

// Two inverse bind matrices equal up to float noise relative to their largest entry.
bool same_matrix(const glm::mat4& a, const glm::mat4& b) {
  float scale = 1.0f, diff = 0.0f;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) {
      scale = std::max({scale, std::abs(a[c][r]), std::abs(b[c][r])});
      diff = std::max(diff, std::abs(a[c][r] - b[c][r]));
    }
  return diff <= 1e-5f * scale;
}

}  // namespace

// Makes a skin validator-clean: inverse bind matrices get an exact affine last row, and no joint
// is listed twice (merge_duplicate_joints).
void Reader::repair_skin(std::size_t index, Skin& skin) {
  const std::string place = "skin " + std::to_string(index);
  std::size_t snapped = 0;
  for (std::size_t j = 0; j < skin.inverse_bind_matrices.size() && skin.had_inverse_bind_matrices; ++j) {
    glm::mat4& m = skin.inverse_bind_matrices[j];
    if (m[0][3] == 0.0f && m[1][3] == 0.0f && m[2][3] == 0.0f && m[3][3] == 1.0f) continue;
    const float off = std::max({std::abs(m[0][3]), std::abs(m[1][3]), std::abs(m[2][3]), std::abs(m[3][3] - 1.0f)});
    if (!(off <= kIbmLastRowTolerance))
      fail(place + ": inverse bind matrix " + std::to_string(j) + " is not affine (its last row is " +
           std::to_string(m[0][3]) + ", " + std::to_string(m[1][3]) + ", " + std::to_string(m[2][3]) + ", " +
           std::to_string(m[3][3]) + "; glTF requires 0, 0, 0, 1)");
    m[0][3] = m[1][3] = m[2][3] = 0.0f;
    m[3][3] = 1.0f;
    ++snapped;
  }
  if (snapped)
    problem("ibm-snapped", snapped,
            {"inverse bind matrix was not exactly affine (last row snapped to 0, 0, 0, 1)",
             "inverse bind matrices were not exactly affine (last row snapped to 0, 0, 0, 1)"},
            place);

  merge_duplicate_joints(index, skin);
}

// A joint listed twice in a skin (the validator's DUPLICATE_ELEMENTS) is listed once: influences
// naming a later listing are remapped to the first (read_influences, through skin_joint_remap_).
// A later listing with another inverse bind matrix cannot be merged without moving its vertices:
// it becomes a new child node of the joint with the identity transform (so it poses exactly like
// the joint), and the skin lists that node instead.
void Reader::merge_duplicate_joints(std::size_t index, Skin& skin) {
  const std::string place = "skin " + std::to_string(index);
  std::vector<std::uint32_t> remap(skin.joints.size());
  std::vector<int> joints;
  std::vector<glm::mat4> matrices;
  std::size_t merged = 0, stand_ins = 0;
  for (std::size_t j = 0; j < skin.joints.size(); ++j) {
    const int node = skin.joints[j];
    const auto first = std::find(joints.begin(), joints.end(), node);
    const bool same = first != joints.end() && same_matrix(matrices[std::size_t(first - joints.begin())],
                                                           skin.inverse_bind_matrices[j]);
    if (same) {
      remap[j] = static_cast<std::uint32_t>(first - joints.begin());
      ++merged;
      continue;
    }
    remap[j] = static_cast<std::uint32_t>(joints.size());
    matrices.push_back(skin.inverse_bind_matrices[j]);
    if (first == joints.end()) {
      joints.push_back(node);
      continue;
    }
    Node stand_in;
    stand_in.name = model_.nodes[std::size_t(node)].name + " (listed again in skin " + std::to_string(index) + ")";
    const int added = static_cast<int>(model_.nodes.size());
    model_.nodes[std::size_t(node)].children.push_back(added);
    model_.nodes.push_back(std::move(stand_in));
    joints.push_back(added);
    ++stand_ins;
  }
  if (skin_joint_remap_.size() <= index) skin_joint_remap_.resize(index + 1);
  if (merged + stand_ins == 0) return;
  skin.joints = std::move(joints);
  skin.inverse_bind_matrices = std::move(matrices);
  skin_joint_remap_[index] = std::move(remap);
  problem("skin-duplicate-joints", merged,
          {"joint listed twice in its skin merged (JOINTS remapped to its first listing)",
           "joints listed twice in their skin merged (JOINTS remapped to their first listing)"},
          place);
  problem("skin-duplicate-joints-stand-in", stand_ins,
          {"joint listed twice in its skin with another inverse bind matrix now lists a new child node of the "
           "joint (identity transform, so it poses the same)",
           "joints listed twice in their skin with other inverse bind matrices now list new child nodes of the "
           "joints (identity transform, so they pose the same)"},
          place);
}

// Extensions and extras on objects that are not carried through (the encoding extensions, whose
// data is decoded, excepted): each named once, with how often it was dropped.
void Reader::note_dropped_extensions() {
  auto encoding = [](const std::string& name) {
    return name == "KHR_draco_mesh_compression" || name == "EXT_meshopt_compression" || name == "KHR_mesh_quantization";
  };
  std::set<std::string> dropped;
  auto check = [&](const json& o, const std::string& where, bool extras_kept) {
    if (!o.is_object()) return;
    if (o.contains("extensions") && o["extensions"].is_object())
      for (const auto& item : o["extensions"].items())
        if (!encoding(item.key())) {
          dropped.insert(item.key());
          problem("extension-dropped", 1,
                  {"extension dropped (not carried through on that object)", "extensions dropped (not carried through on those objects)"},
                  item.key());
        }
    if (!extras_kept && o.contains("extras"))
      problem("extras-dropped", 1, {"object's extras dropped (not carried through)", "objects' extras dropped (not carried through)"},
              where);
  };
  auto each = [&](const char* key, const char* what, bool extras_kept) {
    if (!raw_.contains(key) || !raw_[key].is_array()) return;
    for (std::size_t i = 0; i < raw_[key].size(); ++i) check(raw_[key][i], std::string(what) + " " + std::to_string(i), extras_kept);
  };
  check(raw_["asset"], "asset", true);
  each("meshes", "mesh", true);
  each("skins", "skin", false);
  each("animations", "animation", false);
  each("scenes", "scene", false);
  each("images", "image", false);
  each("accessors", "accessor", false);
  each("bufferViews", "bufferView", false);
  each("buffers", "buffer", false);
  if (raw_.contains("meshes") && raw_["meshes"].is_array())
    for (std::size_t m = 0; m < raw_["meshes"].size(); ++m)
      if (raw_["meshes"][m].is_object() && raw_["meshes"][m].contains("primitives") && raw_["meshes"][m]["primitives"].is_array())
        for (const auto& p : raw_["meshes"][m]["primitives"]) check(p, "", true);
  if (raw_.contains("animations") && raw_["animations"].is_array())
    for (std::size_t a = 0; a < raw_["animations"].size(); ++a)
      for (const char* key : {"channels", "samplers"})
        if (raw_["animations"][a].is_object() && raw_["animations"][a].contains(key) && raw_["animations"][a][key].is_array())
          for (const auto& c : raw_["animations"][a][key]) {
            check(c, "animation " + std::to_string(a) + " " + (key[0] == 'c' ? "channel" : "sampler"), false);
            if (c.is_object() && c.contains("target")) check(c["target"], "animation " + std::to_string(a) + " channel target", false);
          }
  // An extension dropped everywhere no longer belongs in extensionsUsed / extensionsRequired.
  std::set<std::string> carried;
  for (const char* key : {"nodes", "materials", "textures", "samplers", "cameras"})
    if (raw_.contains(key)) collect_extension_names(raw_[key], carried);
  if (raw_.contains("extensions") && raw_["extensions"].is_object())
    for (const auto& item : raw_["extensions"].items()) carried.insert(item.key());
  auto gone = [&](const std::string& e) { return dropped.count(e) && !carried.count(e); };
  for (auto* list : {&model_.extensions_used, &model_.extensions_required})
    list->erase(std::remove_if(list->begin(), list->end(), gone), list->end());
}

}  // namespace deepcut::gltf_detail
