#pragma once
// Certificates for the TLS tests, made at test time with the openssl command (Debian's
// `openssl`, in scripts/install-deps.sh) so none is committed and none expires in the
// repository: a CA, a server certificate it signed for localhost and 127.0.0.1, a client
// certificate it signed, a second CA that signed nothing of the server's, and broken files.
// P-256 keys: quick to make on a loaded machine.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

namespace tessera::test {

class TestCertificates {
 public:
  explicit TestCertificates(std::filesystem::path dir) : dir_(std::move(dir)) {
    std::filesystem::create_directories(dir_);
    write("server.ext", "subjectAltName=DNS:localhost,IP:127.0.0.1\n");
    write("client.ext", "extendedKeyUsage=clientAuth\n");
    make_ca("ca");
    make_ca("other-ca");
    make_signed("server", "localhost", "ca", "server.ext", 2);
    make_signed("client", "render-farm-client", "ca", "client.ext", 2);
    make_signed("rogue-client", "rogue", "other-ca", "client.ext", 2);
    make_signed("expired", "localhost", "ca", "server.ext", -1);
    openssl("pkey -in server.key -aes256 -passout pass:secret -out encrypted.key");
    write("not-pem.txt", "this is not a certificate\n");
  }

  std::filesystem::path path(const std::string& name) const { return dir_ / name; }
  std::string pem(const std::string& name) const {
    std::ifstream in(path(name), std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

  std::filesystem::path ca() const { return path("ca.crt"); }
  std::filesystem::path other_ca() const { return path("other-ca.crt"); }
  std::filesystem::path server_cert() const { return path("server.crt"); }
  std::filesystem::path server_key() const { return path("server.key"); }

 private:
  void write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
  }

  void openssl(const std::string& arguments) const {
    const std::string command =
        "cd '" + dir_.string() + "' && openssl " + arguments + " >> openssl.log 2>&1";
    if (std::system(command.c_str()) != 0)
      throw std::runtime_error("openssl failed (is Debian's openssl installed?): openssl " +
                               arguments + "; see " + (dir_ / "openssl.log").string());
  }

  void make_ca(const std::string& name) const {
    openssl("req -x509 -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -keyout " + name +
            ".key -out " + name + ".crt -days 2 -subj '/CN=Tessera test " + name + "'");
  }

  // A certificate for `common_name` that `ca` signed, valid for `days` (negative: expired).
  void make_signed(const std::string& name, const std::string& common_name, const std::string& ca,
                   const std::string& extensions, int days) const {
    openssl("req -newkey ec -pkeyopt ec_paramgen_curve:prime256v1 -nodes -keyout " + name +
            ".key -out " + name + ".csr -subj '/CN=" + common_name + "'");
    openssl("x509 -req -in " + name + ".csr -CA " + ca + ".crt -CAkey " + ca +
            ".key -CAcreateserial -out " + name + ".crt -days " + std::to_string(days) +
            " -extfile " + extensions);
  }

  std::filesystem::path dir_;
};

}  // namespace tessera::test
