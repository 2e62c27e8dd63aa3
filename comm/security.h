#pragma once
// DDS Security (OMG DDS Security 1.1) through Cyclone's built-in plugins, Debian's
// libddsc0debian: every participant authenticates with an X.509 identity from a shared CA, and
// signed governance and permissions documents say who may publish and subscribe on which topic
// and how traffic is protected. Off by default; scripts/make_pki.sh makes the files.
//
// Who wrote a sample: with security on, the handshake binds a participant's GUID to its
// certificate (Cyclone refuses a peer whose GUID prefix does not begin with the first 47 bits of
// the SHA-256 of its certificate's subject), and signed RTPS messages bind every sample to the
// participant that sent it. Cyclone 0.10's C API does not expose a peer's subject name, so a writer's identity is
// its participant's GUID prefix: 12 hex digits of its certificate's subject fingerprint, a dash,
// 12 of the participant itself (WriterIdentity).

#include <dds/dds.h>

#include <string>

#include "comm/security_config.h"

namespace flsd::dds {

// When enabled: what is wrong with the files, naming `where`, the key and the file (one missing or
// unreadable, a private key readable by anyone but its owner); empty if nothing is.
std::string SecurityFilesError(const SecurityConfig& config, const std::string& where);

// A participant's security file (an identity's security.yaml from scripts/make_pki.sh): its
// security: section, whose files, when enabled, pass SecurityFilesError. InputError naming the
// file otherwise.
SecurityConfig LoadSecurityFile(const std::string& path);

// Adds the dds.sec.* properties of an enabled config to a participant's QoS.
void SetSecurityQos(dds_qos_t* qos, const SecurityConfig& config);

// The same settings as Cyclone's XML (a <Domain><Security> section), for tools that read only
// CYCLONEDDS_URI, such as ddsperf.
std::string SecurityXml(const SecurityConfig& config);

// "<subject fingerprint>-<participant>": 24 hex digits of a participant GUID's prefix.
std::string ParticipantIdentity(const dds_guid_t& participant);

// A certificate's subject, as identities carry it: `fingerprint` is what WriterIdentity gives
// every participant of this certificate as its first 12 hex digits (the first 47 bits of the
// SHA-256 of the DER subject, behind a flag bit); `name` is the subject in RFC 2253 form. Throws
// Error naming the file if it holds no PEM certificate.
struct CertificateSubject {
  std::string fingerprint, name;
};
CertificateSubject ReadCertificateSubject(const std::string& pem_path);

// The identity of the participant whose writer `publication` (a sample's publication_handle)
// matched `reader`; empty if the writer is no longer matched.
std::string WriterIdentity(dds_entity_t reader, dds_instance_handle_t publication);

}  // namespace flsd::dds
