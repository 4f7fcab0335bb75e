// Leak-sanitizer suppressions for the renderer's tests, linked only into them: Mesa (llvmpipe's
// LLVM JIT, the DRI driver, GLX and EGL) keeps allocations until process exit that LeakSanitizer
// reports as leaks. Only those libraries are suppressed; leaks in Parallax's own code still fail.
extern "C" const char* __lsan_default_suppressions() {
  return "leak:libLLVM\n"
         "leak:swrast_dri\n"
         "leak:libgallium\n"
         "leak:libEGL_mesa\n"
         "leak:libGLX_mesa\n"
         "leak:libglapi\n"
         "leak:libX11\n"
         "leak:libxcb\n"
         "leak:libdrm\n";
}
