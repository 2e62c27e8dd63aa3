#include "comm/security.h"

#include <openssl/bio.h>
#include <openssl/pem.h>
#include <openssl/sha.h>
#include <openssl/x509.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <memory>
#include <vector>

#include "comm/dds.h"
#include "core/check.h"
#include "core/config.h"

namespace flsd::dds {
namespace {

// The plugins, which Cyclone finds by library name.
struct Plugin {
  const char* kind;  // in the property names: dds.sec.<kind>.library.path
  const char* library;
  const char* init;
  const char* finalize;
};
constexpr Plugin kPlugins[] = {
    {"auth", "dds_security_auth", "init_authentication", "finalize_authentication"},
    {"crypto", "dds_security_crypto", "init_crypto", "finalize_crypto"},
    {"access", "dds_security_ac", "init_access_control", "finalize_access_control"},
};

// (property, config key, value) of the six files.
struct File {
  const char* property;
  const char* key;
  const std::string* path;
};

std::vector<File> Files(const SecurityConfig& c) {
  return {{"dds.sec.auth.identity_ca", "identity_ca", &c.identity_ca},
          {"dds.sec.auth.identity_certificate", "identity_certificate", &c.identity_certificate},
          {"dds.sec.auth.private_key", "private_key", &c.private_key},
          {"dds.sec.access.permissions_ca", "permissions_ca", &c.permissions_ca},
          {"dds.sec.access.governance", "governance", &c.governance},
          {"dds.sec.access.permissions", "permissions", &c.permissions}};
}

}  // namespace

std::string SecurityFilesError(const SecurityConfig& config, const std::string& where) {
  if (!config.enabled) return "";
  for (const File& f : Files(config)) {
    const std::string at = where + " security." + f.key;
    if (f.path->empty()) return at + ": a file is required when security is enabled";
    if (access(f.path->c_str(), R_OK) != 0) return at + ": cannot read " + *f.path;
  }
  struct stat st {};
  if (stat(config.private_key.c_str(), &st) == 0 && (st.st_mode & (S_IRWXG | S_IRWXO)) != 0) {
    char mode[8];
    std::snprintf(mode, sizeof mode, "%04o", static_cast<unsigned>(st.st_mode & 07777));
    return where + " security.private_key: " + config.private_key + " has mode " + mode +
           "; a private key must be readable by its owner only (chmod 600)";
  }
  return "";
}

SecurityConfig LoadSecurityFile(const std::string& path) {
  const SecurityConfig config = LoadConfigSection<SecurityConfig>(path, "security");
  if (const std::string error = SecurityFilesError(config, path + ":"); !error.empty()) throw InputError(error);
  return config;
}

void SetSecurityQos(dds_qos_t* qos, const SecurityConfig& config) {
  if (!config.enabled) return;
  for (const File& f : Files(config)) dds_qset_prop(qos, f.property, ("file:" + *f.path).c_str());
  for (const Plugin& p : kPlugins) {
    const std::string prefix = std::string("dds.sec.") + p.kind + ".library.";
    dds_qset_prop(qos, (prefix + "path").c_str(), p.library);
    dds_qset_prop(qos, (prefix + "init").c_str(), p.init);
    dds_qset_prop(qos, (prefix + "finalize").c_str(), p.finalize);
  }
}

std::string SecurityXml(const SecurityConfig& c) {
  if (!c.enabled) return "";
  const auto library = [](const Plugin& p) {
    return std::string("<Library path=\"") + p.library + "\" initFunction=\"" + p.init + "\" finalizeFunction=\"" +
           p.finalize + "\"/>";
  };
  const auto file = [](const char* element, const std::string& path) {
    return std::string("<") + element + ">file:" + path + "</" + element + ">";
  };
  return "<CycloneDDS xmlns=\"https://cdds.io/config\"><Domain Id=\"any\"><Security><Authentication>" +
         library(kPlugins[0]) + file("IdentityCA", c.identity_ca) +
         file("IdentityCertificate", c.identity_certificate) + file("PrivateKey", c.private_key) +
         "</Authentication><Cryptographic>" + library(kPlugins[1]) + "</Cryptographic><AccessControl>" +
         library(kPlugins[2]) + file("PermissionsCA", c.permissions_ca) + file("Governance", c.governance) +
         file("Permissions", c.permissions) + "</AccessControl></Security></Domain></CycloneDDS>";
}

std::string ParticipantIdentity(const dds_guid_t& participant) {
  char text[26];
  for (int i = 0; i < 12; ++i) std::snprintf(text + 2 * i + (i >= 6), 3, "%02x", participant.v[i]);
  text[12] = '-';
  return text;
}

CertificateSubject ReadCertificateSubject(const std::string& pem_path) {
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(pem_path.c_str(), "r"), &std::fclose);
  if (!file) throw Error("cannot read certificate " + pem_path);
  std::unique_ptr<X509, void (*)(X509*)> cert(PEM_read_X509(file.get(), nullptr, nullptr, nullptr), &X509_free);
  if (!cert) throw Error(pem_path + " holds no PEM certificate");
  const X509_NAME* subject = X509_get_subject_name(cert.get());
  unsigned char* der = nullptr;
  const int size = i2d_X509_NAME(subject, &der);
  if (size <= 0) throw Error(pem_path + ": cannot encode the certificate's subject");
  unsigned char hash[SHA256_DIGEST_LENGTH];
  SHA256(der, static_cast<size_t>(size), hash);
  OPENSSL_free(der);
  // As the authentication plugin adjusts a participant's GUID: a flag bit, then 47 bits of the hash.
  dds_guid_t prefix{};
  unsigned char carry = 0x80;
  for (int i = 0; i < 6; ++i) {
    prefix.v[i] = static_cast<unsigned char>(carry | hash[i] >> 1);
    carry = static_cast<unsigned char>(hash[i] << 7);
  }
  CertificateSubject result;
  result.fingerprint = ParticipantIdentity(prefix).substr(0, 12);
  std::unique_ptr<BIO, int (*)(BIO*)> text(BIO_new(BIO_s_mem()), &BIO_free);
  X509_NAME_print_ex(text.get(), subject, 0, XN_FLAG_RFC2253);
  char* data = nullptr;
  const long length = BIO_get_mem_data(text.get(), &data);
  result.name.assign(data, static_cast<size_t>(length));
  return result;
}

std::string WriterIdentity(dds_entity_t reader, dds_instance_handle_t publication) {
  dds_builtintopic_endpoint_t* writer = dds_get_matched_publication_data(reader, publication);
  if (writer == nullptr) return "";
  std::string identity = ParticipantIdentity(writer->participant_key);
  dds_builtintopic_free_endpoint(writer);
  return identity;
}

}  // namespace flsd::dds
