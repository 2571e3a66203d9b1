#pragma once
// OpenImageIO through its Python package: the module's backend for TIFF, EXR, HDR and metadata by
// name where the plugin (the system's OpenImageIO) is missing.
namespace panoproj {

// Registers it (oiio_plugin.hpp set_oiio_fallback); the package is imported on first use.
void use_oiio_package();

}  // namespace panoproj
