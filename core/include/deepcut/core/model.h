// SPDX-License-Identifier: MIT
#pragma once
/// @file model.h
/// A glTF scene as the library sees it: node hierarchy, skins, animations, meshes whose triangle
/// primitives are welded `SurfaceMesh`es, and everything the library does not edit (materials,
/// textures, images, samplers, cameras, extensions) carried through untouched as glTF JSON text.

#include <optional>
#include <string>
#include <vector>

#include "deepcut/core/surface_mesh.h"
#include "deepcut/core/types.h"

namespace deepcut {

struct Node {
  std::string name;
  std::vector<int> children;
  glm::vec3 translation{0.0f};
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  ///< w, x, y, z
  glm::vec3 scale{1.0f};
  std::optional<glm::mat4> matrix;  ///< set when the file gave `matrix` instead of TRS
  int mesh = -1;
  int skin = -1;
  int camera = -1;
  /// glTF `node.weights`: morph weights overriding its mesh's `weights` (empty when absent).
  std::vector<float> weights;
  std::string extras_json;      ///< the node's `extras`, verbatim ("" when absent)
  std::string extensions_json;  ///< the node's `extensions`, verbatim ("" when absent)

  /// Local transform from TRS (or `matrix`).
  glm::mat4 local_matrix() const;
};

struct Skin {
  std::string name;
  std::vector<int> joints;                          ///< node indices
  std::vector<glm::mat4> inverse_bind_matrices;     ///< one per joint (identity when the file had none)
  bool had_inverse_bind_matrices = true;            ///< false if the file omitted them
  int skeleton = -1;                                ///< node index of the skeleton root, or -1
};

enum class Interpolation { Step, Linear, CubicSpline };
enum class AnimationPath { Translation, Rotation, Scale, Weights };

struct AnimationSampler {
  std::vector<float> input;   ///< key times in seconds, increasing
  std::vector<float> output;  ///< values: components per key (x3 for CubicSpline: in-tangent, value, out-tangent)
  int components = 3;         ///< 3 translation/scale, 4 rotation (x, y, z, w), N for weights
  Interpolation interpolation = Interpolation::Linear;
};

struct AnimationChannel {
  int sampler = -1;
  int node = -1;
  AnimationPath path = AnimationPath::Translation;
};

struct Animation {
  std::string name;
  std::vector<AnimationSampler> samplers;
  std::vector<AnimationChannel> channels;
  /// Last key time over all samplers (0 for an empty animation).
  float duration() const;
};

/// Triangle primitive. The mesh is welded: glTF's seam-duplicated vertices are one vertex here,
/// with the seam kept in the corner attributes.
struct Primitive {
  SurfaceMesh mesh;
  int material = -1;
  std::string extras_json;
  std::size_t gltf_vertices = 0;  ///< POSITION count in the file it came from (0 if made in code)
  std::size_t welded_merged = 0;  ///< how many glTF vertices weld merged into others
};

struct Mesh {
  std::string name;
  std::vector<Primitive> primitives;
  std::string extras_json;  ///< verbatim; holds `targetNames` when the file named its targets
  /// Default morph weight of each target (glTF `mesh.weights`, zeros when absent): one entry per
  /// morph target, so its size is the mesh's target count (every primitive carries that many).
  std::vector<float> weights;
  /// `extras.targetNames` when present and of the right length (read-only convenience for UIs;
  /// the file's text stays in `extras_json`).
  std::vector<std::string> target_names;
  std::size_t target_count() const { return weights.size(); }
};

/// A glTF image: its encoded bytes (PNG, JPEG, ...), whatever the file stored it as.
struct Image {
  std::string name;
  std::string mime_type;
  std::vector<unsigned char> data;
};

/// Carried-through glTF objects, verbatim JSON text. Texture `source` and material texture
/// indices refer to the model's `images` / `textures` lists unchanged.
struct PassthroughObject {
  std::string name;
  std::string json;
};

/// One kind of loss or repair the importer made, aggregated over the file: every command that
/// reads a model names each kind once (stderr, `--json` "problems", the studio's Problems panel).
struct ImportProblem {
  /// Stable key for scripts and tests ("weights-normalised", "skin-duplicate-joints", ...).
  std::string kind;
  /// One line for people, with the count and where it happened.
  std::string message;
  /// How many things it concerns (vertices, influences, matrices, primitives, ...), summed over
  /// the places it happened.
  std::size_t count = 0;
  /// Where it happened ("mesh 0 'Body' primitive 1", "skin 0"), in file order; empty for the
  /// whole file.
  std::vector<std::string> places;
};

struct Model {
  std::vector<Node> nodes;
  std::vector<std::vector<int>> scenes;  ///< root nodes per scene
  int default_scene = 0;
  std::vector<Skin> skins;
  std::vector<Animation> animations;
  std::vector<Mesh> meshes;
  std::vector<Image> images;
  std::vector<PassthroughObject> materials;
  std::vector<PassthroughObject> textures;
  std::vector<PassthroughObject> samplers;
  std::vector<PassthroughObject> cameras;
  std::vector<std::string> extensions_used;
  std::vector<std::string> extensions_required;
  std::string extras_json;      ///< root `extras` (the operation history lives here)
  std::string extensions_json;  ///< root `extensions`, verbatim ("" when absent)
  std::string asset_copyright;
  std::string asset_extras_json;  ///< `asset.extras`, verbatim (licence attribution lives here)
  /// What the importer repaired or dropped, one entry per kind (file order of first occurrence).
  std::vector<ImportProblem> import_problems;

  /// Roots of the default scene (all parentless nodes when the file had no scene).
  std::vector<int> root_nodes() const;
  /// Parent of each node (-1 for roots).
  std::vector<int> parents() const;
};

}  // namespace deepcut
