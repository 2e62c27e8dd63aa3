#pragma once
// Where a participant's DDS Security files are (comm/security.h uses them): a plain config, with
// no DDS type, so that the server's config can hold it without bringing DDS along.

#include <string>

namespace flsd::dds {

struct SecurityConfig {
  bool enabled = false;
  std::string identity_ca;           // PEM: the CA that signs every participant's identity
  std::string identity_certificate;  // PEM: this participant's certificate
  std::string private_key;           // PEM: its key, readable by the owner only
  std::string permissions_ca;        // PEM: the CA that signed governance and permissions
  std::string governance;            // S/MIME-signed governance document (.p7s)
  std::string permissions;           // S/MIME-signed permissions of this participant (.p7s)
  template <class V>
  void Visit(V& v) {
    v("enabled", enabled);
    v("identity_ca", identity_ca);
    v("identity_certificate", identity_certificate);
    v("private_key", private_key);
    v("permissions_ca", permissions_ca);
    v("governance", governance);
    v("permissions", permissions);
  }
};

}  // namespace flsd::dds
