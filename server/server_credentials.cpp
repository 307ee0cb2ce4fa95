#include "server/server_credentials.hpp"

#include <grpcpp/security/server_credentials.h>
#include <openssl/bio.h>
#include <openssl/err.h>
#include <openssl/pem.h>
#include <openssl/x509.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

namespace tessera::server {
namespace {

struct BioFree {
  void operator()(BIO* bio) const { BIO_free(bio); }
};
struct X509Free {
  void operator()(X509* cert) const { X509_free(cert); }
};
struct KeyFree {
  void operator()(EVP_PKEY* key) const { EVP_PKEY_free(key); }
};
using Bio = std::unique_ptr<BIO, BioFree>;
using Certificate = std::unique_ptr<X509, X509Free>;
using PrivateKey = std::unique_ptr<EVP_PKEY, KeyFree>;

std::string where(const char* key, const std::filesystem::path& path) {
  return std::string(key) + ": '" + path.string() + "'";
}

std::string read_pem(const char* key, const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in || std::filesystem::is_directory(path))
    throw ConfigError(where(key, path) + ": cannot read the file (" + std::strerror(errno) + ")");
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

Bio memory_bio(const std::string& pem) {
  Bio bio(BIO_new_mem_buf(pem.data(), static_cast<int>(pem.size())));
  if (!bio) throw std::runtime_error("OpenSSL could not allocate a memory BIO");
  return bio;
}

// Every certificate of a PEM file, in order (a chain: the leaf first).
std::vector<Certificate> read_certificates(const char* key, const std::filesystem::path& path,
                                           const std::string& pem) {
  const Bio bio = memory_bio(pem);
  std::vector<Certificate> certificates;
  while (X509* cert = PEM_read_bio_X509(bio.get(), nullptr, nullptr, nullptr))
    certificates.emplace_back(cert);
  ERR_clear_error();  // the read past the last certificate fails by design
  if (certificates.empty())
    throw ConfigError(where(key, path) +
                      ": holds no PEM certificate (a '-----BEGIN CERTIFICATE-----' block)");
  return certificates;
}

// Encrypted keys are refused rather than prompted for: a daemon has no one to ask.
int no_passphrase(char*, int, int, void*) {
  return -1;
}

void check_tls_files(const DaemonConfig& config, const std::string& cert_pem,
                     const std::string& key_pem, const std::string& client_ca_pem) {
  const auto chain = read_certificates("tls_cert", config.tls_cert, cert_pem);
  const Certificate& leaf = chain.front();
  if (X509_cmp_current_time(X509_get0_notAfter(leaf.get())) <= 0)
    throw ConfigError(where("tls_cert", config.tls_cert) +
                      ": the certificate has expired; every client would refuse it");

  const Bio key_bio = memory_bio(key_pem);
  const PrivateKey key(PEM_read_bio_PrivateKey(key_bio.get(), nullptr, no_passphrase, nullptr));
  ERR_clear_error();
  if (!key)
    throw ConfigError(where("tls_key", config.tls_key) +
                      ": holds no PEM private key, or an encrypted one (tesserad needs it "
                      "unencrypted; protect the file with its permissions)");
  if (X509_check_private_key(leaf.get(), key.get()) != 1) {
    ERR_clear_error();
    throw ConfigError(where("tls_key", config.tls_key) +
                      ": is not the private key of the certificate in tls_cert ('" +
                      config.tls_cert.string() + "')");
  }
  if (!config.tls_client_ca.empty())
    read_certificates("tls_client_ca", config.tls_client_ca, client_ca_pem);
}

}  // namespace

std::shared_ptr<grpc::ServerCredentials> make_server_credentials(const DaemonConfig& config) {
  if (config.tls_cert.empty()) return grpc::InsecureServerCredentials();
  const std::string cert_pem = read_pem("tls_cert", config.tls_cert);
  const std::string key_pem = read_pem("tls_key", config.tls_key);
  const std::string client_ca_pem = config.tls_client_ca.empty()
                                        ? std::string()
                                        : read_pem("tls_client_ca", config.tls_client_ca);
  check_tls_files(config, cert_pem, key_pem, client_ca_pem);

  grpc::SslServerCredentialsOptions options(
      client_ca_pem.empty() ? GRPC_SSL_DONT_REQUEST_CLIENT_CERTIFICATE
                            : GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY);
  options.pem_root_certs = client_ca_pem;
  options.pem_key_cert_pairs.push_back({key_pem, cert_pem});
  return grpc::SslServerCredentials(options);
}

}  // namespace tessera::server
