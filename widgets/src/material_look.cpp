// SPDX-License-Identifier: MIT
#include "deepcut/widgets/material_look.h"

#include <nlohmann/json.hpp>

namespace deepcut {

MaterialLook material_look(const Model& model, int material) {
  MaterialLook look;
  if (material < 0 || material >= static_cast<int>(model.materials.size())) return look;
  look.base_color = glm::vec4(1.0f);
  const PassthroughObject& object = model.materials[static_cast<std::size_t>(material)];
  look.name = object.name;
  const auto json = nlohmann::json::parse(object.json, nullptr, /*allow_exceptions=*/false);
  if (!json.is_object()) return look;
  look.double_sided = json.value("doubleSided", false);
  look.blend = json.value("alphaMode", std::string("OPAQUE")) == "BLEND";
  const auto pbr = json.find("pbrMetallicRoughness");
  if (pbr == json.end() || !pbr->is_object()) return look;
  const auto factor = pbr->find("baseColorFactor");
  if (factor != pbr->end() && factor->is_array() && factor->size() == 4) {
    for (int i = 0; i < 4; ++i)
      if ((*factor)[static_cast<std::size_t>(i)].is_number())
        look.base_color[i] = (*factor)[static_cast<std::size_t>(i)].get<float>();
  }
  if (pbr->contains("metallicFactor") && (*pbr)["metallicFactor"].is_number())
    look.metallic = (*pbr)["metallicFactor"].get<float>();
  if (pbr->contains("roughnessFactor") && (*pbr)["roughnessFactor"].is_number())
    look.roughness = (*pbr)["roughnessFactor"].get<float>();
  const auto texture = pbr->find("baseColorTexture");
  if (texture == pbr->end() || !texture->is_object() || !texture->contains("index")) return look;
  const auto& index = (*texture)["index"];
  if (!index.is_number_integer()) return look;
  const int t = index.get<int>();
  if (t < 0 || t >= static_cast<int>(model.textures.size())) return look;
  look.texcoord = texture->value("texCoord", 0);
  const auto tex_json =
      nlohmann::json::parse(model.textures[static_cast<std::size_t>(t)].json, nullptr, false);
  if (!tex_json.is_object() || !tex_json.contains("source") || !tex_json["source"].is_number_integer())
    return look;
  const int source = tex_json["source"].get<int>();
  if (source >= 0 && source < static_cast<int>(model.images.size())) look.base_color_image = source;
  return look;
}

}  // namespace deepcut
