// The device kernel for every shape the device path supports (path_tracer_kernel.cuh).
#include "path_tracer_kernel.cuh"

namespace tessera::cuda {

template TESSERA_DEVICE_LAUNCH(kDeviceAllShapes);
template TESSERA_DEVICE_RESOURCES(kDeviceAllShapes);

}  // namespace tessera::cuda
