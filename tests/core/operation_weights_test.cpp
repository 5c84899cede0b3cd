// SPDX-License-Identifier: MIT
// Operations carry the morph weights set by hand (Operation::weights): history files keep them,
// and apply_operation poses the model at them, exactly as if they were the node's own weights.
#include <gtest/gtest.h>

#include "deepcut/core/errors.h"
#include "deepcut/core/generate/cactus.h"
#include "deepcut/core/ops/operation.h"

namespace deepcut {
namespace {

Model small_cactus() {
  CactusOptions options;
  options.target_triangles = 3000;
  return make_cactus(options);
}

int mesh_node(const Model& model) {
  for (std::size_t n = 0; n < model.nodes.size(); ++n)
    if (model.nodes[n].mesh >= 0) return static_cast<int>(n);
  return -1;
}

// A cut across the top of the trunk, at rest.
Operation top_cut() {
  Operation op;
  CutOperation cut;
  cut.plane = {{0.0f, 9.3f, 0.0f}, glm::normalize(glm::vec3(0.2f, 1.0f, 0.1f))};
  op.params = cut;
  op.animation = -1;
  return op;
}

std::vector<std::vector<glm::vec3>> all_positions(const Model& model) {
  std::vector<std::vector<glm::vec3>> out;
  for (const Mesh& m : model.meshes)
    for (const Primitive& p : m.primitives) out.push_back(p.mesh.positions());
  return out;
}

}  // namespace

TEST(OperationWeightsTest, history_files_keep_the_weights_set_by_hand) {
  History history;
  Operation op = top_cut();
  op.weights = {{1, {1.0f, 0.25f}}, {7, {0.5f}}};
  history.operations.push_back(op);
  const History back = parse_history(history_to_json(history));
  ASSERT_EQ(back.operations.size(), 1u);
  EXPECT_EQ(back.operations[0].weights, op.weights);
  history.operations[0].weights.clear();
  EXPECT_EQ(history_to_json(history).find("weights"), std::string::npos) << "absent when none are set";
  EXPECT_THROW(parse_history(R"({"operations":[{"op":"cut","plane":[0,0,0,0,1,0],"weights":[1]}]})"), Error);
  EXPECT_THROW(parse_history(R"({"operations":[{"op":"cut","plane":[0,0,0,0,1,0],"weights":{"x":[1]}}]})"), Error);
  EXPECT_THROW(parse_history(R"({"operations":[{"op":"cut","plane":[0,0,0,0,1,0],"weights":{"1":["a"]}}]})"), Error);
}

TEST(OperationWeightsTest, an_operation_is_made_at_its_weights_as_if_they_were_the_nodes_own) {
  const Model cactus = small_cactus();
  const int node = mesh_node(cactus);
  ASSERT_GE(node, 0);
  const std::vector<float> bloom = {0.0f, 1.0f};  // the bloom swollen through the plane

  Model by_hand = cactus;
  Operation op = top_cut();
  op.weights = {{node, bloom}};
  ASSERT_EQ(apply_operation(by_hand, op).status, OpStatus::Ok);

  Model own = cactus;
  own.nodes[static_cast<std::size_t>(node)].weights = bloom;
  ASSERT_EQ(apply_operation(own, top_cut()).status, OpStatus::Ok);

  Model plain = cactus;
  ASSERT_EQ(apply_operation(plain, top_cut()).status, OpStatus::Ok);

  EXPECT_EQ(all_positions(by_hand), all_positions(own)) << "the same cut, vertex for vertex";
  EXPECT_NE(all_positions(by_hand), all_positions(plain)) << "the weights change where the cut runs";
  EXPECT_EQ(model_history(by_hand).operations.at(0).weights, op.weights) << "the model's history keeps them";
}

}  // namespace deepcut
