#pragma once

namespace tessera::schema {

// Field paths in the user's own terms: a YAML file says `geometry[3].radius` and
// `render.spp`, a protobuf request `geometry[3].sphere.radius` and
// `settings.samples_per_pixel`. Validation writes each path once, in the style asked for,
// instead of rewriting messages afterwards.
enum class PathStyle { kYaml, kProto };

}  // namespace tessera::schema
