// The base colour texture of each material of a model, as one backend makes textures: clraster's
// Texture or the OpenGL oracle's GlTexture. Shared so that both backends draw a model with the same
// textures, and treat the same materials as having none.
#pragma once

#include "clraster/clraster.hpp"
#include "io/model_loader.hpp"

#include <array>
#include <cstddef>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace clraster::frontend {

// The texel of the texture that parts without an image are drawn with: sampled as 1, it leaves the
// base colour factor as it is.
inline constexpr std::array<std::byte, 4> kWhiteTexel{std::byte{255}, std::byte{255}, std::byte{255}, std::byte{255}};

// The model's texture coordinates, or (0, 0) for every vertex when it has none: the attribute uv.
inline std::vector<float> texcoords_or_zeros(const io::Model& model) {
  return model.texcoords.empty() ? std::vector<float>(2 * model.vertex_count(), 0.0f) : model.texcoords;
}

// What errors and warnings call a material's image: its file, or its reference in the model file.
inline std::string image_name(const io::MaterialTexture& image) {
  return image.embedded() ? "the embedded image '" + image.reference + "'" : image.file;
}

template <typename Texture>
class MaterialTextures {
 public:
  // Makes the texture of a material's image: RGBA8 holding the texels as the image stores them (not
  // decoded from sRGB: programs/material.cl says why), with mipmaps, and with the image's bottom row
  // at t = 0 (where texture coordinates put it, see io::Mesh::texcoords). Throws clraster::Error
  // when the image cannot be read or decoded.
  using Loader = std::function<Texture(const io::MaterialTexture& image)>;

  // Each material of `model` gets its image's texture, or `white` (1x1, white) when it has no image,
  // when the model has no texture coordinates to map one (sampled at (0, 0), the texture would
  // colour the whole part with one texel), or when the image cannot be read or decoded. The last two
  // add a line to `warnings`: the model still renders, coloured by the base colour factors. So do
  // the loader's Model::material_warnings (textures it could not pass on, or not as meant).
  MaterialTextures(const io::Model& model, Texture white, const Loader& load, std::vector<std::string>& warnings)
      : white_(std::move(white)) {
    warnings.insert(warnings.end(), model.material_warnings.begin(), model.material_warnings.end());
    for (std::size_t i = 0; i < model.materials.size(); ++i) {
      const std::optional<io::MaterialTexture>& image = model.materials[i].base_color_texture;
      std::optional<Texture>& texture = textures_.emplace_back();
      if (!image) continue;
      const std::string material = io::material_label(model.materials[i], i);
      if (model.texcoords.empty()) {
        warnings.push_back(material + ": the model has no texture coordinates to map its base colour texture " +
                           image_name(*image) + "; drawn with its base colour factor only");
        continue;
      }
      try {
        texture.emplace(load(*image));
      } catch (const Error& error) {
        warnings.push_back(material + ": " + error.what() + "; drawn with its base colour factor only");
      }
    }
  }

  // The texture of model material `index`.
  const Texture& operator[](std::size_t index) const {
    const std::optional<Texture>& texture = textures_.at(index);
    return texture ? *texture : white_;
  }

 private:
  Texture white_;
  std::vector<std::optional<Texture>> textures_;  // per material; empty: white_
};

}  // namespace clraster::frontend
