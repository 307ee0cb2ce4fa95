#include "mesh_files.hpp"

#include <bit>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

#include "tessera/scene/mesh_loader.hpp"

namespace tessera::bench {

IndexedMesh load_mesh_with_assimp(const std::filesystem::path& path) {
  const TriangleMeshDesc desc = load_mesh_file(path);
  IndexedMesh mesh;
  mesh.positions.reserve(desc.positions.size());
  for (const auto& p : desc.positions) mesh.positions.emplace_back(p);
  mesh.indices = desc.indices;
  return mesh;
}

namespace {

struct PlyProperty {
  std::string type;        // scalar type, or the index type of a list
  std::string count_type;  // non-empty for lists
  std::string name;
};

struct PlyElement {
  std::string name;
  std::size_t count = 0;
  std::vector<PlyProperty> properties;
};

std::size_t scalar_size(const std::string& type, const std::filesystem::path& path) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" ||
      type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  throw std::runtime_error(path.string() + ": unknown PLY type " + type);
}

std::uint32_t read_unsigned(const char* p, std::size_t size) {
  if (size == 1) return static_cast<unsigned char>(*p);
  if (size == 2) {
    std::uint16_t v;
    std::memcpy(&v, p, 2);
    return v;
  }
  std::uint32_t v;
  std::memcpy(&v, p, 4);
  return v;
}

}  // namespace

IndexedMesh load_binary_ply_direct(const std::filesystem::path& path) {
  static_assert(std::endian::native == std::endian::little);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path.string() + ": cannot open");
  std::vector<PlyElement> elements;
  std::string line;
  std::getline(in, line);
  if (line != "ply") throw std::runtime_error(path.string() + ": not a PLY file");
  bool binary_le = false;
  while (std::getline(in, line)) {
    std::istringstream words(line);
    std::string keyword;
    words >> keyword;
    if (keyword == "format") {
      std::string format;
      words >> format;
      binary_le = format == "binary_little_endian";
    } else if (keyword == "element") {
      PlyElement e;
      words >> e.name >> e.count;
      elements.push_back(e);
    } else if (keyword == "property") {
      if (elements.empty()) throw std::runtime_error(path.string() + ": property before element");
      PlyProperty p;
      words >> p.type;
      if (p.type == "list") words >> p.count_type >> p.type;
      words >> p.name;
      elements.back().properties.push_back(p);
    } else if (keyword == "end_header") {
      break;
    }
  }
  if (!binary_le)
    throw std::runtime_error(path.string() + ": only binary_little_endian PLY is supported");

  const auto body_start = in.tellg();
  in.seekg(0, std::ios::end);
  const auto body_size = static_cast<std::size_t>(in.tellg() - body_start);
  std::vector<char> body(body_size);
  in.seekg(body_start);
  in.read(body.data(), static_cast<std::streamsize>(body_size));
  const char* cursor = body.data();
  const char* const end = body.data() + body.size();
  const auto need = [&](std::size_t bytes) {
    if (static_cast<std::size_t>(end - cursor) < bytes)
      throw std::runtime_error(path.string() + ": truncated");
  };

  IndexedMesh mesh;
  for (const PlyElement& e : elements) {
    if (e.name == "vertex") {
      std::size_t stride = 0;
      int offsets[3] = {-1, -1, -1};
      for (const auto& p : e.properties) {
        if (!p.count_type.empty())
          throw std::runtime_error(path.string() + ": list property in vertex");
        const int axis = p.name == "x" ? 0 : p.name == "y" ? 1 : p.name == "z" ? 2 : -1;
        if (axis >= 0) {
          if (scalar_size(p.type, path) != 4 || p.type.find("int") != std::string::npos)
            throw std::runtime_error(path.string() + ": vertex coordinates must be float");
          offsets[axis] = static_cast<int>(stride);
        }
        stride += scalar_size(p.type, path);
      }
      if (offsets[0] < 0 || offsets[1] < 0 || offsets[2] < 0)
        throw std::runtime_error(path.string() + ": vertex lacks x, y or z");
      need(stride * e.count);
      mesh.positions.resize(e.count);
      for (std::size_t i = 0; i < e.count; ++i, cursor += stride)
        for (int axis = 0; axis < 3; ++axis)
          std::memcpy(&mesh.positions[i][axis], cursor + offsets[axis], 4);
    } else if (e.name == "face") {
      if (e.properties.size() != 1 || e.properties[0].count_type.empty())
        throw std::runtime_error(path.string() + ": face must hold exactly one index list");
      const std::size_t count_size = scalar_size(e.properties[0].count_type, path);
      const std::size_t index_size = scalar_size(e.properties[0].type, path);
      mesh.indices.reserve(e.count * 3);
      for (std::size_t f = 0; f < e.count; ++f) {
        need(count_size);
        const std::uint32_t n = read_unsigned(cursor, count_size);
        cursor += count_size;
        need(n * index_size);
        const std::uint32_t first = read_unsigned(cursor, index_size);
        for (std::uint32_t k = 2; k < n; ++k) {
          mesh.indices.push_back(first);
          mesh.indices.push_back(read_unsigned(cursor + (k - 1) * index_size, index_size));
          mesh.indices.push_back(read_unsigned(cursor + k * index_size, index_size));
        }
        cursor += n * index_size;
      }
    } else {
      throw std::runtime_error(path.string() + ": unsupported PLY element " + e.name);
    }
  }
  for (std::uint32_t index : mesh.indices)
    if (index >= mesh.positions.size())
      throw std::runtime_error(path.string() + ": vertex index out of range");
  return mesh;
}

void write_binary_ply(const std::filesystem::path& path, const IndexedMesh& mesh) {
  static_assert(std::endian::native == std::endian::little);
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) throw std::runtime_error(path.string() + ": cannot create");
  out << "ply\nformat binary_little_endian 1.0\ncomment written by tessera-bench\n"
      << "element vertex " << mesh.positions.size()
      << "\nproperty float x\nproperty float y\nproperty float z\n"
      << "element face " << mesh.triangle_count()
      << "\nproperty list uchar uint vertex_indices\nend_header\n";
  out.write(reinterpret_cast<const char*>(mesh.positions.data()),
            static_cast<std::streamsize>(mesh.positions.size() * sizeof(vec3)));
  std::vector<char> faces(mesh.triangle_count() * 13);
  for (std::size_t t = 0; t < mesh.triangle_count(); ++t) {
    faces[t * 13] = 3;
    std::memcpy(&faces[t * 13 + 1], &mesh.indices[t * 3], 12);
  }
  out.write(faces.data(), static_cast<std::streamsize>(faces.size()));
  if (!out) throw std::runtime_error(path.string() + ": write failed");
}

std::vector<Triangle> to_triangles(const IndexedMesh& mesh) {
  std::vector<Triangle> triangles(mesh.triangle_count());
  for (std::size_t t = 0; t < triangles.size(); ++t)
    triangles[t] =
        Triangle{mesh.positions[mesh.indices[3 * t]], mesh.positions[mesh.indices[3 * t + 1]],
                 mesh.positions[mesh.indices[3 * t + 2]], 0};
  return triangles;
}

}  // namespace tessera::bench
