// SPDX-License-Identifier: MIT
#pragma once
// The golden corpus: seeded random `deepcut` command lines over every asset model, and the
// hashes of what they produce (see golden_corpus_test.cpp for the file format and how to record).

#include <cstdint>
#include <string>
#include <vector>

namespace deepcut::golden {

/// One corpus operation: `command` starts with "deepcut " and names its inputs and its output
/// relative to the run directory (assets/..., out/ID.glb, hist/ID.json).
struct CorpusOp {
  std::string id;
  std::string command;
  std::string history;  ///< text of hist/ID.json for `deepcut apply` ("" for other commands)
};

/// The asset models the corpus covers, relative to the repository root ("assets/cactus.glb").
std::vector<std::string> corpus_assets();

/// Every corpus operation, from fixed seeds: planes, blades and drill axes placed through points
/// of each model's posed surface (a few placed to miss), short random histories for `apply`, and
/// a few malformed command lines. Reads the models with plugins::read_model.
/// @param assets_dir  the repository's assets/ folder.
std::vector<CorpusOp> generate_corpus(const std::string& assets_dir);

/// 64-bit FNV-1a.
std::uint64_t fnv1a(const std::string& bytes);

}  // namespace deepcut::golden
