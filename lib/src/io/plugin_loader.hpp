#pragma once
// Opening a plugin (a shared module built with panoproj that links a heavy library: OpenImageIO,
// FFmpeg) on first use. Looked for: $<env> if set, else beside the executable or Python module
// holding this code, in ../lib/panoproj/ (a bin/ folder's: an install, pip's scripts) or
// ../panoproj/ (a repaired wheel's panoproj.scripts/) from there, else the install's and the
// build's library folders. Never closed (the libraries keep threads and caches).
#include <atomic>
#include <mutex>
#include <string>

namespace panoproj {

// The address of the plugin `file`'s `make_symbol` (a function the caller casts to its type and
// calls), once its `abi_symbol` returns `abi`; null and `error` set to why not ("not found (...)",
// "not loadable: ...", "not this panoproj's").
void* load_plugin(const char* file, const char* env, const char* abi_symbol, int abi,
                  const char* make_symbol, std::string& error);

// A plugin's backend, loaded on the first get() (once, whichever thread asks); null where it
// cannot be, and error() says why (every later get() the same).
template <class Backend>
class Plugin {
 public:
  constexpr Plugin(const char* file, const char* env, const char* abi_symbol, int abi,
                   const char* make_symbol)
      : file_(file), env_(env), abi_symbol_(abi_symbol), make_symbol_(make_symbol), abi_(abi) {}
  Backend* get() {
    std::call_once(once_, [this] {
      if (void* make = load_plugin(file_, env_, abi_symbol_, abi_, make_symbol_, error_))
        backend_ = reinterpret_cast<Backend* (*)()>(make)();
      loaded_ = backend_ != nullptr;
    });
    return backend_;
  }
  const std::string& error() const { return error_; }
  const char* file() const { return file_; }
  bool loaded() const { return loaded_; }  // (without loading it)

 private:
  const char *file_, *env_, *abi_symbol_, *make_symbol_;
  int abi_;
  std::once_flag once_;
  Backend* backend_ = nullptr;
  std::string error_;
  std::atomic<bool> loaded_{false};
};

}  // namespace panoproj
