// The device kernel for scenes of spheres, rectangles and triangles (path_tracer_kernel.cuh).
#include "path_tracer_kernel.cuh"

namespace tessera::cuda {

template TESSERA_DEVICE_LAUNCH(kDeviceCommonShapes);
template TESSERA_DEVICE_RESOURCES(kDeviceCommonShapes);

}  // namespace tessera::cuda
