#include "server/yaml_document.hpp"

#include "server/config.hpp"

namespace tessera::server {

YAML::Node parse_yaml_document(const std::string& text, const std::string& display_name) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    std::string where = display_name;
    if (!e.mark.is_null()) where.append(":").append(std::to_string(e.mark.line + 1));
    throw ConfigError(where + ": YAML syntax error: " + e.msg);
  }
}

}  // namespace tessera::server
