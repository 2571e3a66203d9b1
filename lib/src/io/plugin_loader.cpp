#include "io/plugin_loader.hpp"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <vector>

#include "panoproj/error.hpp"

#ifndef PANOPROJ_PLUGIN_DIRS
#define PANOPROJ_PLUGIN_DIRS ""
#endif

namespace panoproj {
namespace {

// Where the code of this library sits: the executable, the Python module or libpanoproj.so.
std::filesystem::path own_folder() {
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&load_plugin), &info) == 0 || !info.dli_fname) return {};
  std::error_code ec;
  const auto p = std::filesystem::canonical(info.dli_fname, ec);
  return ec ? std::filesystem::path() : p.parent_path();
}

std::vector<std::string> candidates(const char* file, const char* env) {
  if (const char* given = std::getenv(env); given && *given) return {given};
  std::vector<std::string> out;
  if (const auto own = own_folder(); !own.empty()) {
    out.push_back((own / file).string());
    out.push_back((own / "panoproj" / file).string());  // beside libpanoproj.so, any libdir
    out.push_back((own.parent_path() / "lib" / "panoproj" / file).string());
    out.push_back((own.parent_path() / "panoproj" / file).string());
  }
  // The install's and the build tree's folders (':'-separated, set by CMake).
  const std::string dirs = PANOPROJ_PLUGIN_DIRS;
  for (size_t at = 0; at < dirs.size();) {
    const size_t end = std::min(dirs.find(':', at), dirs.size());
    if (end > at) out.push_back(dirs.substr(at, end - at) + "/" + file);
    at = end + 1;
  }
  return out;
}

}  // namespace

void* load_plugin(const char* file, const char* env, const char* abi_symbol, int abi,
                  const char* make_symbol, std::string& error) {
  std::string tried;
  for (const std::string& path : candidates(file, env)) {
    std::error_code ec;
    if (!std::filesystem::exists(path, ec)) {
      tried += (tried.empty() ? "" : ", ") + path;
      continue;
    }
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle) {
      error = "not loadable: " + one_line(dlerror());
      return nullptr;
    }
    auto abi_of = reinterpret_cast<int (*)()>(dlsym(handle, abi_symbol));
    void* make = dlsym(handle, make_symbol);
    if (!abi_of || !make || abi_of() != abi) {
      error = "not this panoproj's: " + path + " (rebuild or reinstall panoproj)";
      return nullptr;
    }
    return make;
  }
  error = std::string("not found (set ") + env + " to its path; looked for " + tried + ")";
  return nullptr;
}

}  // namespace panoproj
