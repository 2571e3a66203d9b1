#pragma once
// Opening a plugin (a shared module built with panoproj that links a heavy library: OpenImageIO,
// FFmpeg) on first use. Looked for: $<env> if set, else beside the executable or Python module
// holding this code, in ../lib/panoproj/ (a bin/ folder's: an install, pip's scripts) or
// ../panoproj/ (a repaired wheel's panoproj.scripts/) from there, else the install's and the
// build's library folders. Never closed (the libraries keep threads and caches).
#include <string>

namespace panoproj {

// The address of the plugin `file`'s `make_symbol` (a function the caller casts to its type and
// calls), once its `abi_symbol` returns `abi`; null and `error` set to why not ("not found (...)",
// "not loadable: ...", "not this panoproj's").
void* load_plugin(const char* file, const char* env, const char* abi_symbol, int abi,
                  const char* make_symbol, std::string& error);

}  // namespace panoproj
