#include "tessera/image/image_codecs.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <cstring>
#include <stdexcept>
#include <system_error>

namespace tessera::image_codecs {
namespace {

constexpr char kModuleName[] = "libtessera_image_codecs.so";

struct Loaded {
  const Table* table = nullptr;
  std::filesystem::path path;
  std::string error;
};

const Loaded& loaded() {
  // Loaded once per process and never closed: the table's functions and the writers'
  // handles must outlive every caller. A failure is kept too, so a missing module costs
  // one search, and every later call reports the same reasons.
  static const Loaded result = [] {
    Loaded l;
    const std::vector<std::filesystem::path> candidates = candidate_paths();
    l.table = open_first(candidates, l.path, l.error);
    return l;
  }();
  return result;
}

}  // namespace

std::vector<std::filesystem::path> candidate_paths() {
  std::vector<std::filesystem::path> paths;
  // An explicit path is the only one: a wrong setting fails loudly instead of quietly
  // loading some other module.
  if (const char* env = std::getenv("TESSERA_IMAGE_CODECS"); env != nullptr && *env != '\0')
    return {std::filesystem::path(env)};
  std::error_code ec;
  const std::filesystem::path program = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (!ec && program.has_parent_path()) {
    const std::filesystem::path dir = program.parent_path();
    paths.push_back(dir.parent_path() / "lib" / "tessera" / kModuleName);
    paths.push_back(dir / kModuleName);
  }
#ifdef TESSERA_IMAGE_CODECS_BUILD_PATH
  paths.emplace_back(TESSERA_IMAGE_CODECS_BUILD_PATH);
#endif
#ifdef TESSERA_IMAGE_CODECS_INSTALL_PATH
  paths.emplace_back(TESSERA_IMAGE_CODECS_INSTALL_PATH);
#endif
  return paths;
}

const Table* open_first(const std::vector<std::filesystem::path>& candidates,
                        std::filesystem::path& opened, std::string& error) {
  error.clear();
  for (const std::filesystem::path& path : candidates) {
    std::error_code ec;
    if (!std::filesystem::is_regular_file(path, ec)) {
      error += "\n  " + path.string() + ": no such file";
      continue;
    }
    // Lazy: binding every function of OpenImageIO's ~260 libraries up front as well
    // (RTLD_NOW) took a 16x16 local render from 1.35 G to 1.46 G instructions. RTLD_LOCAL
    // keeps their symbols out of the program's scope.
    void* handle = dlopen(path.c_str(), RTLD_LAZY | RTLD_LOCAL);
    if (handle == nullptr) {
      const char* why = dlerror();
      error += "\n  " + path.string() + ": " + (why != nullptr ? why : "dlopen failed");
      continue;
    }
    void* entry = dlsym(handle, kEntryPoint);
    if (entry == nullptr) {
      error += "\n  " + path.string() + ": not the image codecs module (no " +
               std::string(kEntryPoint) + ")";
      dlclose(handle);
      continue;
    }
    // POSIX guarantees that a dlsym result converts to a function pointer.
    const Table* table = reinterpret_cast<EntryPointFunction>(entry)();
    if (table == nullptr || table->abi == nullptr || std::strcmp(table->abi, kAbi) != 0) {
      error += "\n  " + path.string() + ": built for \"" +
               (table != nullptr && table->abi != nullptr ? table->abi : "?") +
               "\", not for this program's \"" + kAbi + "\"";
      dlclose(handle);
      continue;
    }
    opened = path;
    return table;
  }
  if (candidates.empty()) error = "\n  (nowhere to look)";
  return nullptr;
}

const Table& table() {
  const Loaded& l = loaded();
  if (l.table == nullptr)
    throw std::runtime_error(
        "cannot read or write images: no usable image codecs module " + std::string(kModuleName) +
        " (OpenImageIO); set TESSERA_IMAGE_CODECS to its path. Looked in:" + l.error);
  return *l.table;
}

}  // namespace tessera::image_codecs

namespace tessera {

std::filesystem::path load_image_codecs() {
  image_codecs::table();
  return image_codecs::loaded().path;
}

}  // namespace tessera
