// Compiled into every program that links parallax::net (an INTERFACE source of the target, see
// CMakeLists.txt), not into the library: a static library's object that nothing calls is left
// out of the link, and its initialiser with it. Here the initialiser is part of the program, so
// http(s) URLs open through core's openByteSource before main runs, and a module below net
// (lod, io) reads a URL without linking the network.
#include "net/network.h"

namespace parallax {
namespace {

[[maybe_unused]] const bool kHttpOpenerInstalled = [] {
  installHttpOpener();
  return true;
}();

}  // namespace
}  // namespace parallax
