// SPDX-License-Identifier: MIT
#pragma once
// The VTK data the studio's view draws a scene instance with, built on any thread (a worker
// opening a model, or the UI thread following a step), its normals overlay, and the stand-in triangle the
// view compiles its shaders with before a model arrives (scene_view.cpp). VTK stays in the .cpp files that
// include this.

#include <vtkSmartPointer.h>

#include <memory>
#include <vector>

#include "deepcut/plugins/scene.h"
#include "deepcut/widgets/material_look.h"
#include "deepcut/widgets/view_poly_data.h"

class vtkCamera;
class vtkPolyData;
class vtkTexture;

namespace deepcut::studio {

/// The material look of scene instance `sp`.
MaterialLook instance_look(const plugins::Scene& scene, const plugins::SceneInstance& sp);

/// Makes the "uv0" array the active texture coordinates of `poly` (`use`) or none. The mapper
/// uploads and interpolates active coordinates even when no texture reads them: a quarter of
/// the corner layout's vertex data. Marks the data modified only when the choice changes.
void use_texture_coords(vtkPolyData* poly, bool use);

/// The full build of an instance's drawn data (the one conversion, on whichever thread), with
/// texture coordinates active when its material's texture reads them (the view makes the final
/// choice: a texture may not decode). An instance without corner normals (a scene made without
/// them, as an open makes it for its first frame) is drawn with its posed normals all the same,
/// each computed for a drawn point only.
std::shared_ptr<ViewPolyData> instance_view_data(const plugins::Scene& scene,
                                                 const plugins::SceneInstance& sp);
/// The same for an instance a step made out of another (a cut's piece: `origin`), taking how its
/// corners share points from `source`, the data drawn for that other instance before the step.
/// `spare` (or null): data no longer drawn and held nowhere else; the one take_smallest_fit
/// chooses by ViewPolyData::room for the instance's cells leaves it, and the new data takes its
/// arrays (their memory reused). `scratch` (or null): the copy's working memory, kept by the
/// caller from copy to copy.
std::shared_ptr<ViewPolyData> instance_view_data(const plugins::Scene& scene,
                                                 const plugins::SceneInstance& sp, const ViewPolyData& source,
                                                 const PrimitiveOrigin& origin,
                                                 std::vector<std::shared_ptr<ViewPolyData>>* spare = nullptr,
                                                 ViewPolyData::CopyScratch* scratch = nullptr);

/// Computes what drawing `data` the first time would otherwise compute on the UI thread, cached
/// until the data changes: the bounds of its cells (the camera's clipping range) and the range
/// of each coordinate (whether the vertex buffer needs a shift and scale). The cells' bounds are
/// the ranges when every point is drawn by some cell (a full build with corner points), kept
/// for the surface mapper (SurfaceMapper::keep_cells_bounds), else VTK computes and caches them.
void compute_draw_caches(const ViewPolyData& data);

/// The normals overlay of the drawn data `drawn`: a line of `length` along each point's normal
/// from the point, or where the data has none, along each face normal from the face centre
/// (what the renderer shades with); every k-th only on big meshes (about 60,000 lines at most),
/// so the view stays readable and responsive.
vtkSmartPointer<vtkPolyData> normal_lines(const std::vector<vtkPolyData*>& drawn, float length);

/// One triangle at the focal point of `camera`, 0.75 of the view's height across and 0.56 high,
/// with normals (and texture coordinates when `textured`): the vertex layout of an instance's
/// data. Drawing it compiles what an instance's first frame needs: it holds a square of a third
/// of the view's height, so whole tiles of the renderer (which compiles separate code for those)
/// in any view over 200 pixels tall, yet shades a fraction of the pixels a triangle over the
/// whole view would, on the cores the open's reader is using.
vtkSmartPointer<vtkPolyData> stand_in_triangle(vtkCamera* camera, bool textured);
/// A one-pixel texture made as a material's is (make_texture).
vtkSmartPointer<vtkTexture> stand_in_texture();
/// One bone and one joint at `camera`'s focal point, drawn as plugins::skeleton_overlay draws a
/// skinned model's (lines and points over the model): drawing them compiles what that overlay
/// needs in the first frame of such a model.
Overlay stand_in_skeleton(vtkCamera* camera);

}  // namespace deepcut::studio
