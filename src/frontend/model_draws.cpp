#include "frontend/model_draws.hpp"

namespace clraster::frontend {

ClrasterModelDraws::ClrasterModelDraws(Context& context, const Program& program, const io::Model& model,
                                       std::vector<std::string>& warnings)
    : program_(&program), parts_(model.parts) {
  for (const io::Material& material : model.materials) base_colors_.push_back(material.base_color_factor);
  if (declares_attribute(program_->interface(), kUvAttribute)) uvs_.emplace(context, texcoords_or_zeros(model));
  if (declares_base_color_texture(program_->interface())) {
    // RGBA8 (srgb false) and flipped vertically, as MaterialTextures::Loader says.
    textures_.emplace(
        model, Texture(context, 1, 1, Format::RGBA8, kWhiteTexel, false),
        [&](const io::MaterialTexture& image) {
          return image.embedded() ? Texture::decode(context, image.encoded, false, true, image_name(image))
                                  : Texture::load(context, image.file, false, true);
        },
        warnings);
  }
}

void ClrasterModelDraws::bind(std::span<const ProgramInputs> views, std::span<const Bindings> own) {
  view_count_ = views.size();
  bindings_.clear();
  bindings_.reserve(parts_.size() * views.size());  // the draws point into it
  for (const io::ModelPart& part : parts_) {
    for (std::size_t view = 0; view < views.size(); ++view) {
      ProgramInputs inputs = views[view];
      inputs.base_color = base_colors_.at(part.material);
      Bindings& bindings = bindings_.emplace_back(own.empty() ? Bindings(*program_) : own[view]);
      for (const ProgramVariable& uniform : program_->interface().uniforms) {
        if (provides_uniform(uniform.name)) bindings.set_bytes(uniform.name, std::as_bytes(inputs.uniform(uniform.name)));
      }
      if (textures_) bindings.set_texture(kBaseColorTexture, (*textures_)[part.material], Sampler{});
    }
  }
}

std::vector<DrawCall> ClrasterModelDraws::calls(const VertexBuffer& vertices, const IndexBuffer& indices,
                                                const DrawState& state) const {
  std::vector<DrawCall> calls;
  for (std::size_t i = 0; i < parts_.size(); ++i) {
    DrawCall& call = calls.emplace_back();
    call.vertices = &vertices;
    call.indices = &indices;
    call.first = parts_[i].first_index;
    call.count = parts_[i].index_count;
    call.state = state;
    call.program = program_;
    call.bindings = &bindings_.at(i * view_count_);
    if (view_count_ > 1) {
      for (std::size_t view = 0; view < view_count_; ++view) {
        call.views.push_back({kIdentity, kIdentity, &bindings_[i * view_count_ + view]});
      }
    }
    if (uvs_) call.attributes.push_back({kUvAttribute, &*uvs_, AttributeType::Float2});
  }
  return calls;
}

}  // namespace clraster::frontend
