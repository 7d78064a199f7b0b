// clraster._clraster: the extension module behind the Python package. Thin: arrays arrive checked
// (python/clraster/ checks dtypes, shapes and layouts and raises ValueError), and every call that
// draws releases the GIL.
#include <nanobind/nanobind.h>
#include <nanobind/ndarray.h>
#include <nanobind/stl/array.h>
#include <nanobind/stl/function.h>
#include <nanobind/stl/optional.h>
#include <nanobind/stl/pair.h>
#include <nanobind/stl/string.h>
#include <nanobind/stl/tuple.h>
#include <nanobind/stl/vector.h>

#include "frontend/program_contract.hpp"
#include "io/camera.hpp"
#include "io/model_loader.hpp"
#include "mesh.hpp"
#include "renderer.hpp"

namespace nb = nanobind;
using namespace nb::literals;

namespace clraster::python {
namespace {

template <typename T, typename... Shape>
using In = nb::ndarray<const T, nb::c_contig, nb::device::cpu, Shape...>;
template <typename T, typename... Shape>
using Out = nb::ndarray<T, nb::c_contig, nb::device::cpu, Shape...>;

template <typename T, typename... Shape>
std::vector<T> copy_of(const In<T, Shape...>& array) {
  return std::vector<T>(array.data(), array.data() + array.size());
}

// A row-major matrix (numpy's, M @ v) as a column-major Mat4.
Mat4 column_major(const float* row_major) {
  Mat4 result;
  for (int row = 0; row < 4; ++row) {
    for (int column = 0; column < 4; ++column) result[4 * column + row] = row_major[4 * row + column];
  }
  return result;
}

std::vector<Mat4> column_major(const In<float, nb::shape<-1, 4, 4>>& matrices) {
  std::vector<Mat4> result;
  for (std::size_t b = 0; b < matrices.shape(0); ++b) result.push_back(column_major(matrices.data() + 16 * b));
  return result;
}

void store_row_major(const glm::mat4& matrix, float* out) {
  for (int row = 0; row < 4; ++row) {
    for (int column = 0; column < 4; ++column) out[4 * row + column] = matrix[column][row];
  }
}

glm::vec3 vec3_at(const In<float, nb::shape<-1, 3>>& points, std::size_t i) {
  return {points(i, 0), points(i, 1), points(i, 2)};
}

io::BuiltinShading builtin_shading(const std::string& name) {
  if (name == "normal") return io::BuiltinShading::Normal;
  if (name == "lambert") return io::BuiltinShading::Lambert;
  if (name == "depth") return io::BuiltinShading::Depth;
  if (name == "overdraw") return io::BuiltinShading::Overdraw;
  throw InvalidArgument("shading must be one of normal, lambert, depth, overdraw, not '" + name + "'");
}

// A compiled program of a context, and a texture of one: shared with the draws that use them.
struct ProgramHandle {
  std::shared_ptr<const Program> program;
};
struct TextureHandle {
  std::shared_ptr<const Texture> texture;
};

// What a program declares, for the package to check values against: uniforms as (name, type,
// array size, bytes, whether the renderer binds it), textures as (name, whether the renderer binds
// it), attributes as (name, type).
nb::dict declarations(const Program& program) {
  const ProgramInterface& interface = program.interface();
  nb::list uniforms, textures, attributes;
  for (const ProgramVariable& u : interface.uniforms) {
    uniforms.append(nb::make_tuple(u.name, u.type, u.array_size, u.bytes, frontend::provides_uniform(u.name)));
  }
  for (const ProgramVariable& t : interface.textures) textures.append(nb::make_tuple(t.name, t.name == frontend::kBaseColorTexture));
  for (const ProgramVariable& a : interface.attributes) attributes.append(nb::make_tuple(a.name, a.type));
  nb::dict result;
  result["uniforms"] = uniforms;
  result["textures"] = textures;
  result["attributes"] = attributes;
  return result;
}

Format texture_format(std::size_t channels, bool floats) {
  switch (channels) {
    case 1: return floats ? Format::R32F : Format::R8;
    case 2: return floats ? Format::RG32F : Format::RG8;
    case 4: return floats ? Format::RGBA32F : Format::RGBA8;
    default: throw InvalidArgument("a texture has 1, 2 or 4 channels, not " + std::to_string(channels));
  }
}

// A Python callable (or None) called with the GIL after each chunk of a batch; what it raises
// (KeyboardInterrupt) ends the batch.
Progress with_gil(std::optional<nb::callable> callback) {
  if (!callback) return {};
  return [callback = std::move(*callback)](std::size_t done, std::size_t total) {
    nb::gil_scoped_acquire acquire;
    callback(done, total);
  };
}

// The Python side of a mesh: a handle on arrays it shares with every context that uploaded them.
struct MeshHandle {
  std::shared_ptr<const MeshData> data;
};

// A read-only numpy view of a mesh's array, which keeps the mesh alive.
template <typename T>
nb::ndarray<nb::numpy, const T, nb::ndim<2>> view_of(const MeshHandle& mesh, const std::vector<T>& values,
                                                     std::size_t columns) {
  return nb::ndarray<nb::numpy, const T, nb::ndim<2>>(values.data(), {values.size() / columns, columns},
                                                      nb::find(&mesh));
}

Pictures pictures_of(std::size_t count, int width, int height) {
  if (width < 1 || height < 1 || width > kMaxFramebufferSize || height > kMaxFramebufferSize) {
    throw InvalidArgument("size " + std::to_string(width) + "x" + std::to_string(height) +
                          " is out of range: each side must be 1.." + std::to_string(kMaxFramebufferSize));
  }
  return {width, height, count};
}

}  // namespace
}  // namespace clraster::python

NB_MODULE(_clraster, m) {
  using namespace clraster;
  using namespace clraster::python;

  // The library's exceptions; InvalidArgument is also a ValueError, as bad arguments are in Python.
  nb::exception<Error> error(m, "Error", PyExc_RuntimeError);
  nb::exception<DeviceError>(m, "DeviceError", error);
  nb::exception<BuildError>(m, "BuildError", error);
  nb::exception<InvalidArgument>(m, "InvalidArgument", nb::make_tuple(error, nb::handle(PyExc_ValueError)));

  m.def("version", &version);
  m.attr("MAX_TEXTURE_SIZE") = kMaxTextureSize;
  m.def("describe_triangles_dropped", &io::describe_triangles_dropped);

  nb::class_<DeviceInfo>(m, "Device")
      .def_ro("index", &DeviceInfo::index)
      .def_ro("name", &DeviceInfo::name)
      .def_ro("platform", &DeviceInfo::platform)
      .def_ro("version", &DeviceInfo::version)
      .def_ro("driver_version", &DeviceInfo::driver_version)
      .def_ro("type", &DeviceInfo::type)
      .def_ro("compute_units", &DeviceInfo::compute_units)
      .def("__repr__", [](const DeviceInfo& d) {
        return "<clraster.Device " + std::to_string(d.index) + ": " + d.name + " (" + d.platform + ", " + d.type +
               ", " + std::to_string(d.compute_units) + " compute units)>";
      });
  m.def("devices", &list_devices);

  nb::class_<MeshHandle>(m, "Mesh")
      .def(
          "__init__",
          [](MeshHandle* self, In<float, nb::shape<-1, 3>> positions, In<std::uint32_t, nb::shape<-1, 3>> indices,
             std::optional<In<float, nb::shape<-1, 3>>> normals, std::optional<In<float, nb::shape<-1, 2>>> uvs) {
            std::optional<std::vector<float>> normal_values, uv_values;
            if (normals) normal_values = copy_of(*normals);
            if (uvs) uv_values = copy_of(*uvs);
            new (self) MeshHandle{make_mesh(copy_of(positions), copy_of(indices), std::move(normal_values),
                                            std::move(uv_values))};
          },
          "positions"_a, "indices"_a, "normals"_a.none(), "uvs"_a.none())
      .def_prop_ro("positions", [](const MeshHandle& h) { return view_of(h, h.data->model.positions, 3); })
      .def_prop_ro("indices", [](const MeshHandle& h) { return view_of(h, h.data->model.indices, 3); })
      .def_prop_ro("normals", [](const MeshHandle& h) { return view_of(h, h.data->model.normals, 3); })
      .def_prop_ro("uvs",
                   [](const MeshHandle& h) {
                     return h.data->model.texcoords.empty()
                                ? std::nullopt
                                : std::optional(view_of(h, h.data->model.texcoords, 2));
                   })
      .def_prop_ro("triangles_dropped", [](const MeshHandle& h) { return h.data->triangles_dropped; })
      .def_prop_ro("materials", [](const MeshHandle& h) {
        nb::list materials;
        for (const io::Material& material : h.data->model.materials) {
          nb::dict entry;
          entry["name"] = material.name;
          entry["base_color"] = nb::make_tuple(material.base_color_factor[0], material.base_color_factor[1],
                                               material.base_color_factor[2], material.base_color_factor[3]);
          entry["texture"] = material.base_color_texture ? nb::cast(material.base_color_texture->reference) : nb::none();
          materials.append(entry);
        }
        return materials;
      });

  m.def(
      "load",
      [](const std::string& path) {
        std::vector<std::string> warnings;
        MeshHandle mesh{load_mesh(path, warnings)};
        return std::make_pair(std::move(mesh), warnings);
      },
      "path"_a, nb::call_guard<nb::gil_scoped_release>());

  // Cameras as the command line makes them (glm in float), so that the same camera gives the same
  // matrices, and so the same picture. Each row of eyes, targets and ups is one camera.
  m.def(
      "look_at",
      [](In<float, nb::shape<-1, 3>> eyes, In<float, nb::shape<-1, 3>> targets, In<float, nb::shape<-1, 3>> ups,
         Out<float, nb::shape<-1, 4, 4>> out) {
        for (std::size_t b = 0; b < eyes.shape(0); ++b) {
          io::Camera camera;
          camera.eye = vec3_at(eyes, b);
          camera.target = vec3_at(targets, b);
          camera.up = vec3_at(ups, b);
          try {
            io::validate_camera(camera);
          } catch (const InvalidArgument& e) {
            throw InvalidArgument("look_at, camera " + std::to_string(b) + ": " + e.what());
          }
          store_row_major(io::view_matrix(camera), out.data() + 16 * b);
        }
      },
      "eyes"_a, "targets"_a, "ups"_a, "out"_a);
  m.def(
      "perspective",
      [](float fov_y_degrees, float aspect, float near_plane, float far_plane, Out<float, nb::shape<4, 4>> out) {
        io::Camera camera;
        camera.fov_degrees = fov_y_degrees;
        camera.near_plane = near_plane;
        camera.far_plane = far_plane;
        io::validate_camera(camera);
        store_row_major(io::projection_matrix(camera, aspect), out.data());
      },
      "fov_y_degrees"_a, "aspect"_a, "near"_a, "far"_a, "out"_a);

  nb::class_<ProgramHandle>(m, "Program")
      .def_prop_ro("declarations", [](const ProgramHandle& p) { return declarations(*p.program); })
      .def_prop_ro("file_name", [](const ProgramHandle& p) { return p.program->file_name(); });
  nb::class_<TextureHandle>(m, "Texture");
  m.def("read_program_file", &Program::read_source, "path"_a);

  nb::class_<Renderer>(m, "Context")
      .def(nb::init<int, std::size_t>(), "device"_a, "memory_cap"_a, nb::call_guard<nb::gil_scoped_release>())
      .def_prop_ro("device", &Renderer::device)
      .def(
          "render",
          [](Renderer& renderer, const MeshHandle& mesh, In<float, nb::shape<-1, 4, 4>> views,
             In<float, nb::shape<4, 4>> projection, const std::string& shading, std::array<float, 2> depth_range,
             Out<std::uint8_t, nb::shape<-1, -1, -1, 4>> out, std::optional<nb::callable> progress) {
            const io::BuiltinShading mode = builtin_shading(shading);
            const std::vector<Mat4> view_matrices = column_major(views);
            const Mat4 projection_matrix = column_major(projection.data());
            const Pictures pictures = pictures_of(out.shape(0), int(out.shape(2)), int(out.shape(1)));
            const Progress report = with_gil(std::move(progress));
            nb::gil_scoped_release release;
            return renderer.render(mesh.data, view_matrices, projection_matrix, mode, depth_range, pictures, out.data(),
                                   report);
          },
          "mesh"_a, "views"_a, "projection"_a, "shading"_a, "depth_range"_a, "out"_a, "progress"_a.none())
      .def(
          "render_program",
          [](Renderer& renderer, const MeshHandle& mesh, In<float, nb::shape<-1, 4, 4>> views,
             In<float, nb::shape<4, 4>> projection, const ProgramHandle& program,
             const std::vector<std::tuple<std::string, nb::bytes, bool>>& uniforms,
             const std::vector<std::pair<std::string, TextureHandle>>& textures,
             Out<std::uint8_t, nb::shape<-1, -1, -1, 4>> out, std::optional<nb::callable> progress) {
            OwnValues own;
            for (const auto& [name, bytes, per_view] : uniforms) {
              const auto* first = static_cast<const std::byte*>(bytes.data());
              own.uniforms.push_back({name, std::vector<std::byte>(first, first + bytes.size()), per_view});
            }
            for (const auto& [name, handle] : textures) own.textures.emplace_back(name, handle.texture);
            const std::vector<Mat4> view_matrices = column_major(views);
            const Mat4 projection_matrix = column_major(projection.data());
            const Pictures pictures = pictures_of(out.shape(0), int(out.shape(2)), int(out.shape(1)));
            const Progress report = with_gil(std::move(progress));
            std::vector<std::string> warnings;
            nb::gil_scoped_release release;
            const std::uint64_t dropped = renderer.render(mesh.data, view_matrices, projection_matrix, program.program,
                                                          own, pictures, out.data(), report, warnings);
            return std::make_pair(dropped, warnings);
          },
          "mesh"_a, "views"_a, "projection"_a, "program"_a, "uniforms"_a, "textures"_a, "out"_a, "progress"_a.none())
      .def(
          "compile",
          [](Renderer& renderer, const std::string& source, const std::string& file_name) {
            return ProgramHandle{renderer.compile(source, file_name)};
          },
          "source"_a, "file_name"_a, nb::call_guard<nb::gil_scoped_release>())
      .def(
          "material_program", [](Renderer& renderer) { return ProgramHandle{renderer.material_program()}; },
          nb::call_guard<nb::gil_scoped_release>())
      .def(
          "texture",
          [](Renderer& renderer, nb::ndarray<nb::ro, nb::c_contig, nb::device::cpu, nb::ndim<3>> image) {
            const bool floats = image.dtype() == nb::dtype<float>();
            const Format format = texture_format(image.shape(2), floats);
            const auto* texels = static_cast<const std::byte*>(image.data());
            const std::span<const std::byte> bytes(texels, image.nbytes());
            nb::gil_scoped_release release;
            return TextureHandle{renderer.texture(int(image.shape(1)), int(image.shape(0)), format, bytes)};
          },
          "image"_a)
      .def(
          "rasterize",
          [](Renderer& renderer, const MeshHandle& mesh, In<float, nb::shape<-1, 4, 4>> views,
             In<float, nb::shape<4, 4>> projection, Out<std::int32_t, nb::shape<-1, -1, -1>> triangles,
             Out<float, nb::shape<-1, -1, -1, 2>> barycentrics, Out<float, nb::shape<-1, -1, -1>> depths,
             std::optional<nb::callable> progress) {
            const std::vector<Mat4> view_matrices = column_major(views);
            const Mat4 projection_matrix = column_major(projection.data());
            const Pictures pictures = pictures_of(triangles.shape(0), int(triangles.shape(2)), int(triangles.shape(1)));
            const Progress report = with_gil(std::move(progress));
            nb::gil_scoped_release release;
            return renderer.rasterize(mesh.data, view_matrices, projection_matrix, pictures,
                                      {triangles.data(), barycentrics.data(), depths.data()}, report);
          },
          "mesh"_a, "views"_a, "projection"_a, "triangles"_a, "barycentrics"_a, "depths"_a, "progress"_a.none())
      .def(
          "rasterize_clip",
          [](Renderer& renderer, In<float, nb::shape<-1, -1, 4>> positions, In<std::uint32_t, nb::shape<-1, 3>> indices,
             Out<std::int32_t, nb::shape<-1, -1, -1>> triangles, Out<float, nb::shape<-1, -1, -1, 2>> barycentrics,
             Out<float, nb::shape<-1, -1, -1>> depths, std::optional<nb::callable> progress) {
            const Pictures pictures = pictures_of(triangles.shape(0), int(triangles.shape(2)), int(triangles.shape(1)));
            if (positions.shape(0) != pictures.count) throw InvalidArgument("one set of clip positions per picture");
            const std::size_t vertex_count = positions.shape(1);
            check_indices(std::span(indices.data(), indices.size()), vertex_count);
            const Progress report = with_gil(std::move(progress));
            nb::gil_scoped_release release;
            return renderer.rasterize(std::span(positions.data(), positions.size()), vertex_count,
                                      std::span(indices.data(), indices.size()), pictures,
                                      {triangles.data(), barycentrics.data(), depths.data()}, report);
          },
          "positions"_a, "indices"_a, "triangles"_a, "barycentrics"_a, "depths"_a, "progress"_a.none());
}
