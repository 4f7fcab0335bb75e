// libFuzzer target for the camera files: a camera (`parallax view` saves it, `render --camera`
// reads it) and a camera path (keyframes, `render --camera-path`). Any bytes must give a camera
// or a path, or an InputError naming the file; never a crash, a hang or an uncaught exception.
// A path that loads is also sampled at a few frames (its interpolation between keyframes).
//
// Input framing: one byte choosing the reader (even: camera, odd: camera path), then the file.
// The readers take a path: the file is a memory file (memfd), a new one each run. Seeds in
// fuzz/corpus/camera_json/ are files as Parallax writes them (cameraToJson, cameraPathToJson).
#include <sys/mman.h>
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <string>

#include "core/error.h"
#include "render/camera.h"
#include "render/camera_path.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  const bool path_file = (data[0] & 1) != 0;
  const int fd = memfd_create("fuzz.json", 0);
  if (fd < 0) return 0;
  std::size_t written = 0;
  while (written < size - 1) {
    const ssize_t n = write(fd, data + 1 + written, size - 1 - written);
    if (n <= 0) break;
    written += std::size_t(n);
  }
  const std::string file = "/proc/self/fd/" + std::to_string(fd);
  try {
    if (path_file) {
      const parallax::CameraPath path = parallax::loadCameraPath(file);
      for (int frame = 0; frame < 5; ++frame) (void)path.frame(frame, 5);
    } else {
      (void)parallax::loadCamera(file);
    }
  } catch (const parallax::InputError&) {
  }
  close(fd);
  return 0;
}
