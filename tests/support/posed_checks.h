// SPDX-License-Identifier: MIT
#pragma once
// The one check that a posed model which followed edits (or was adopted from a worker) describes
// its model as a fresh build at the same pose does. It returns what differs instead of asserting,
// so GoogleTest (`EXPECT_EQ(..., "")`) and QtTest (`QVERIFY2(d.empty(), d.c_str())`) share it.

#include <string>

#include "deepcut/core/model.h"
#include "deepcut/core/posed_model.h"

namespace deepcut::test {

/// The first difference between `got` and `fresh` (built from the same model at the same pose),
/// or "" when they agree: the same instances of the same meshes, posed positions, linear maps,
/// morph weights and bounds bit for bit, and grids that hold the same number of faces and answer
/// a query over the bounds with the same faces. Gridless instances compare without their grid.
std::string posed_model_difference(const PosedModel& got, const PosedModel& fresh);

/// `posed_model_difference` against a fresh build of `model` at `got`'s pose.
std::string difference_from_fresh_build(const PosedModel& got, const Model& model);

}  // namespace deepcut::test
