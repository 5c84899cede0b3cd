// SPDX-License-Identifier: MIT
// SceneView following the scene's steps: an edit in place updates the instances' data
// (ViewPolyData::update); a structural step keeps the data of the instances it kept, brings back
// what an undo or redo restores, copies a cut's pieces from the data of what they were cut out
// of, and sets aside what left for a later undo. The widget, drawing and picking are in
// scene_view.cpp.
#include <vtkPolyData.h>

#include <memory>
#include <string>
#include <vector>

#include "deepcut/widgets/poly_data_bridge.h"
#include "instance_data.h"
#include "scene_view_impl.h"

namespace deepcut::studio {

void SceneView::update_scene(const ModelChange& change) {
  Impl& d = *impl_;
  if (!d.scene) return;
  if (change.structure) return d.follow_structure(change);
  for (const PrimitiveChange& edit : change.primitives)
    for (std::size_t i = 0; i < d.instances.size() && i < d.scene->instances.size(); ++i) {
      const plugins::SceneInstance& sp = d.scene->instances[i];
      if (sp.mesh == edit.mesh && sp.primitive == edit.primitive)
        d.instances[i].data->update(*sp.surface, sp.posed(), &sp.posed_normals, edit);
    }
  if (d.show_normals) d.rebuild_normals();
}

std::shared_ptr<ViewPolyData> SceneView::Impl::built_data(const plugins::SceneInstance& sp,
                                                          const ModelChange& change,
                                                          const std::vector<InstanceActor>& old,
                                                          std::vector<std::shared_ptr<ViewPolyData>>& spare) {
  for (const auto& o : change.origins) {
    if (!o || o->node != sp.node || o->mesh != sp.mesh || o->primitive != sp.primitive) continue;
    for (const InstanceActor& from : old)
      if (from.data && from.node == o->node_before && from.mesh == o->mesh_before &&
          from.primitive == o->primitive_before)
        return instance_view_data(*scene, sp, *from.data, *o, &spare, &copy_scratch);
  }
  return instance_view_data(*scene, sp);
}

void SceneView::prepare_updates() {
  for (InstanceActor& instance : impl_->instances) instance.data->prepare_updates();
}

void SceneView::Impl::follow_structure(const ModelChange& change) {
  std::vector<InstanceActor> old;
  old.swap(instances);
  for (InstanceActor& instance : old) renderer->RemoveActor(instance.actor);
  picker->InitializePickList();
  decltype(stash) back;  // only what comes back (the rest is spare: a copy reuses its arrays)
  using Kind = plugins::InstanceOrigin::Kind;
  for (const plugins::InstanceOrigin& origin : scene->origins)
    if (const auto it = stash.find(origin.key); origin.kind == Kind::Stashed && it != stash.end())
      back.insert(*it);
  std::vector<std::shared_ptr<ViewPolyData>> spare;
  for (auto& [key, data] : stash)
    if (!back.count(key) && data && data.use_count() == 1) spare.push_back(std::move(data));
  stash.clear();
  std::vector<std::string> notes;
  for (std::size_t i = 0; i < scene->instances.size(); ++i) {
    const plugins::SceneInstance& sp = scene->instances[i];
    const plugins::InstanceOrigin origin =
        i < scene->origins.size() ? scene->origins[i] : plugins::InstanceOrigin();
    std::shared_ptr<ViewPolyData> data;
    if (origin.kind == Kind::Kept && origin.instance < old.size() && old[origin.instance].data) {
      InstanceActor& from = old[origin.instance];  // displaced positions go back to the pose
      if (from.displaced) from.data->set_positions(sp.posed(), nullptr);
      data = std::move(from.data);
    } else if (const auto it = back.find(origin.key); origin.kind == Kind::Stashed && it != back.end()) {
      data = std::move(it->second);
    }
    // (A guard: data of another state than the scene's.)
    if (data && static_cast<std::size_t>(data->poly()->GetNumberOfCells()) != sp.surface->face_slots())
      data = nullptr;
    if (data) clear_colors(data->poly());  // the inspectors colour again
    add_actor(sp, data ? std::move(data) : built_data(sp, change, old, spare), notes);
  }
  for (const auto& [j, key] : scene->departed)  // (displaced data is not kept: built again)
    if (j < old.size() && old[j].data && !old[j].displaced) stash[key] = std::move(old[j].data);
  rebuild_normals();
}

}  // namespace deepcut::studio
