#pragma once
// An X display for off-screen pictures. Debian's VTK 9.1 renders through GLX even when the
// window is off-screen, so without an X server it aborts the process. When DISPLAY is unset
// this starts a virtual X server of our own (Xvfb, as a child process), points DISPLAY at it
// for this process and ends it when the process exits: the picture commands then work over
// ssh and in CI without `xvfb-run`.
#include <string>

namespace tearflow {

/// Makes sure this process has an X display: nothing when DISPLAY is set; otherwise starts
/// `Xvfb -displayfd FD -screen 0 1600x1200x24 -nolisten tcp` once per process, reads the
/// display number it chose, sets DISPLAY=":N" and terminates the server at exit (the server
/// also ends when this process dies by a signal: call this from the main thread, whose end
/// the kernel reports to it).
/// The environment variable TEARFLOW_XVFB, when set, names the server program instead.
/// `purpose` (e.g. "render 'flow.png'") heads the InputError when Xvfb is missing or fails
/// to start. Returns the display in use.
std::string ensure_display(const std::string& purpose);

} // namespace tearflow
