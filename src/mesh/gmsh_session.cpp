#include "mesh/gmsh_session.hpp"

#include <gmsh.h>

namespace tearflow::mesh {

namespace {
std::recursive_mutex gmsh_mutex;
int gmsh_depth = 0; // nesting depth of live sessions; guarded by gmsh_mutex
} // namespace

GmshSession::GmshSession(bool verbose) : lock_(gmsh_mutex) {
  if (gmsh_depth == 0) {
    with_gmsh("Gmsh initialization", [verbose] {
      // readConfigFiles = false: a user's ~/.gmshrc must not change our meshes.
      gmsh::initialize(0, nullptr, false);
      try {
        // initialize() turns the terminal on; turn it off before anything can print.
        gmsh::option::setNumber("General.Terminal", verbose ? 1 : 0);
        // Errors throw (the 4.8 default once initialized; set it so that it stays true).
        gmsh::option::setNumber("General.AbortOnError", 2);
      } catch (...) {
        gmsh::finalize();
        throw;
      }
    });
  }
  ++gmsh_depth;
}

GmshSession::~GmshSession() {
  if (--gmsh_depth == 0) {
    try {
      gmsh::finalize();
    } catch (...) { // a destructor must not throw; nothing useful to do here
    }
  }
}

} // namespace tearflow::mesh
