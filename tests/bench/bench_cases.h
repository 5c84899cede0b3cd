// SPDX-License-Identifier: MIT
#pragma once
// Benchmark registration shared by bench_main.cpp. Case names are "<case>/<impl>/<size>":
// impl "ours" or the peer's name; size "25k" (the default cactus) or "1M".

#include <string>
#include <vector>

#include <vtkNew.h>
#include <vtkCylinder.h>
#include <vtkPlane.h>

#include "deepcut/core/ops/drill.h"
#include "deepcut/core/types.h"

namespace deepcut::bench {

struct Quoted {
  std::string name;  ///< case name
  double paper_ms;   ///< the paper's figure (i7-7700HQ), quoted, not measured
  std::string note;
};

/// Registers every case; `with_1m` adds the ~1M-triangle variants.
void register_cases(bool with_1m);

/// Registers the model-level cases (model_cases.cpp) for the cactus of `triangles` triangles,
/// named "<case>/<impl>/<size>", each run `iterations` times per repetition.
void register_model_cases(std::size_t triangles, const std::string& size, int iterations);

/// The VTK plane of `p` (unit normal): the peers' clip function for the cut cases.
vtkNew<vtkPlane> vtk_plane(const Plane& p);
/// The infinite VTK cylinder around the drill axis of `cyl` (taken along z, as every drill case
/// aims): the peers' clip function for the drill cases (no depth bound, no round rim).
vtkNew<vtkCylinder> vtk_cylinder(const Cylinder& cyl);

/// The paper's Table 1 / Table 2 figures the cases are compared with.
std::vector<Quoted> quoted_figures();

struct MemoryReport {
  double mesh_mb = 0, extra_peak_mb = 0, ratio = 0;
  std::size_t triangles = 0;
};
/// Peak RSS added by a cut (both sides, attributes, adjacency update) on the ~1M model, measured
/// in a child process (VmHWM reset through /proc/self/clear_refs).
MemoryReport measure_cut_memory();

}  // namespace deepcut::bench
