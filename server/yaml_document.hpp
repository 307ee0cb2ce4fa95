#pragma once
#include <yaml-cpp/yaml.h>

#include <string>

namespace tessera::server {

// Parses a configuration document (tesserad's settings file, the tokens file), turning a
// YAML syntax error into a ConfigError (config.hpp) that names `display_name` and
// the line.
YAML::Node parse_yaml_document(const std::string& text, const std::string& display_name);

}  // namespace tessera::server
