#pragma once
// RAII access to the Gmsh SDK. gmsh::initialize/finalize act on one global state, and Gmsh
// is not thread-safe, so a session holds a process-wide lock for its lifetime. Sessions nest
// (on one thread): only the outermost one initializes and finalizes, and nested ones share
// its model. Finalizing after every outermost use matters: after Gmsh throws in the middle
// of gmsh::open it stays "busy" and silently ignores later opens until it is re-initialized.
//
// Gmsh 4.8's C++ API reports errors (with General.AbortOnError = 2, its default once
// initialized) by throwing a std::string; with_gmsh() turns that into an InputError.
#include <exception>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>

#include "core/error.hpp"
#include "mesh/mesh.hpp"

namespace tearflow::mesh {

class GmshSession {
public:
  /// `verbose` lets Gmsh print its progress to the terminal; by default it prints nothing.
  explicit GmshSession(bool verbose = false);
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

private:
  std::unique_lock<std::recursive_mutex> lock_;
};

/// Runs `f` (which calls the Gmsh API) and rethrows Gmsh's errors as InputError prefixed by
/// `context` (e.g. "mesh file 'a.msh'"). InputErrors thrown by `f` itself pass unchanged.
template <typename F> decltype(auto) with_gmsh(std::string_view context, F&& f) {
  try {
    return std::forward<F>(f)();
  } catch (const InputError&) {
    throw;
  } catch (const std::string& e) { // Gmsh 4.8
    input_error("{}: Gmsh: {}", context, e);
  } catch (const std::exception& e) { // later Gmsh versions, OpenCASCADE, allocation
    input_error("{}: Gmsh: {}", context, e.what());
  }
}

/// The mesh of the current Gmsh model (inside a GmshSession): linear tets of every volume,
/// regions from 3D physical groups (unnamed ones become "region<tag>"; "fluid" when there are
/// none), faces from 2D physical groups (unnamed: "face<tag>"). Coordinates are multiplied
/// by `length_scale`; `source` names the mesh in messages. Node tags become 0-based indices
/// in Gmsh's node order; unused nodes are kept (see drop_unused_nodes). Call it through
/// with_gmsh: Gmsh errors come out as std::string.
Mesh mesh_from_gmsh_model(double length_scale, const std::string& source);

} // namespace tearflow::mesh
