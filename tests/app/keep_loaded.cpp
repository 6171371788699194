// Preloaded (LD_PRELOAD) into the window tests under AddressSanitizer. Every dlopen also gets
// RTLD_NODELETE, so a library loaded at run time (SDL's X11 and OpenGL helpers, Mesa's DRI driver
// and what it pulls in) stays mapped after its dlclose. LeakSanitizer scans the process at exit:
// once a library is unmapped, the blocks its globals pointed to look leaked and its frames read
// "<unknown module>", which no suppression can name. Kept mapped, those blocks are reachable and
// a real leak names its library (tests/app/lsan.supp).
#include <dlfcn.h>

extern "C" void* dlopen(const char* file, int mode) {
  using DlOpen = void* (*)(const char*, int);
  // the next dlopen: AddressSanitizer's interceptor, then the C library's
  static const DlOpen next = reinterpret_cast<DlOpen>(dlsym(RTLD_NEXT, "dlopen"));
  return next(file, mode | RTLD_NODELETE);
}
