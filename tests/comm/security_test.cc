// The DDS Security settings: what is wrong with a config is said by key and file, the properties
// and Cyclone's XML carry the same files, and identities read as the GUID prefix they come from.

#include "comm/security.h"

#include "comm/dds.h"

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <memory>
#include <string>
#include <utility>

#include "tests/common/test_support.h"

namespace flsd::dds {
namespace {

using ::testing::HasSubstr;

class SecurityConfigTest : public ::testing::Test {
 protected:
  void SetUp() override {
    for (std::string* path : {&config_.identity_ca, &config_.identity_certificate, &config_.private_key,
                              &config_.permissions_ca, &config_.governance, &config_.permissions}) {
      files_.push_back(std::make_unique<testutil::TempFile>(".pem", "x"));
      *path = files_.back()->path();
    }
    chmod(config_.private_key.c_str(), 0600);
    config_.enabled = true;
  }

  SecurityConfig config_;
  std::vector<std::unique_ptr<testutil::TempFile>> files_;
};

TEST_F(SecurityConfigTest, ReadableFilesAndAnOwnerOnlyKeyPass) {
  EXPECT_EQ(SecurityFilesError(config_, "server.yaml:"), "");
  SecurityConfig off;
  EXPECT_EQ(SecurityFilesError(off, "server.yaml:"), "");  // off: nothing is needed
}

TEST_F(SecurityConfigTest, AMissingFileIsNamedByKeyAndPath) {
  config_.governance = "/nonexistent/governance.p7s";
  EXPECT_EQ(SecurityFilesError(config_, "server.yaml:"),
            "server.yaml: security.governance: cannot read /nonexistent/governance.p7s");
  config_.permissions_ca.clear();
  EXPECT_EQ(SecurityFilesError(config_, "server.yaml:"),
            "server.yaml: security.permissions_ca: a file is required when security is enabled");
}

TEST_F(SecurityConfigTest, AKeyOthersCanReadIsRefused) {
  chmod(config_.private_key.c_str(), 0644);
  EXPECT_EQ(SecurityFilesError(config_, "op.yaml:"), "op.yaml: security.private_key: " + config_.private_key +
                                                         " has mode 0644; a private key must be readable by its "
                                                         "owner only (chmod 600)");
}

TEST_F(SecurityConfigTest, ASecurityFileLoadsWithItsFilesChecked) {
  std::string yaml = "security:\n  enabled: true\n";
  for (const auto& [key, path] : {std::pair{"identity_ca", config_.identity_ca},
                                  {"identity_certificate", config_.identity_certificate},
                                  {"private_key", config_.private_key},
                                  {"permissions_ca", config_.permissions_ca},
                                  {"governance", config_.governance},
                                  {"permissions", config_.permissions}}) {
    yaml += std::string("  ") + key + ": " + path + "\n";
  }
  const testutil::TempFile file(".yaml", yaml);
  const SecurityConfig loaded = LoadSecurityFile(file.path());
  EXPECT_TRUE(loaded.enabled);
  EXPECT_EQ(loaded.private_key, config_.private_key);
  EXPECT_EQ(loaded.permissions, config_.permissions);
  chmod(config_.private_key.c_str(), 0644);
  EXPECT_THAT(testutil::InputErrorMessage([&] { LoadSecurityFile(file.path()); }),
              HasSubstr(file.path() + ": security.private_key: " + config_.private_key + " has mode 0644"));
  const testutil::TempFile none(".yaml", "domain_id: 3\n");
  EXPECT_EQ(testutil::InputErrorMessage([&] { LoadSecurityFile(none.path()); }),
            none.path() + ": missing section 'security'");
}

TEST_F(SecurityConfigTest, PropertiesAndXmlNameTheSameFilesAndPlugins) {
  dds_qos_t* qos = dds_create_qos();
  SetSecurityQos(qos, config_);
  char* value = nullptr;
  ASSERT_TRUE(dds_qget_prop(qos, "dds.sec.access.governance", &value));
  EXPECT_EQ(std::string(value), "file:" + config_.governance);
  dds_free(value);
  ASSERT_TRUE(dds_qget_prop(qos, "dds.sec.crypto.library.path", &value));
  EXPECT_STREQ(value, "dds_security_crypto");
  dds_free(value);
  dds_delete_qos(qos);
  const std::string xml = SecurityXml(config_);
  EXPECT_THAT(xml, HasSubstr("<PrivateKey>file:" + config_.private_key + "</PrivateKey>"));
  EXPECT_THAT(xml, HasSubstr("<Permissions>file:" + config_.permissions + "</Permissions>"));
  EXPECT_THAT(xml, HasSubstr("path=\"dds_security_ac\" initFunction=\"init_access_control\""));
  EXPECT_EQ(SecurityXml(SecurityConfig{}), "");
}

TEST(CertificateSubjectTest, AFileWithoutACertificateIsNamed) {
  const testutil::TempFile key(".pem", "-----BEGIN PRIVATE KEY-----\nAAAA\n-----END PRIVATE KEY-----\n");
  try {
    ReadCertificateSubject(key.path());
    ADD_FAILURE() << "a key was read as a certificate";
  } catch (const Error& e) {
    EXPECT_EQ(std::string(e.what()), key.path() + " holds no PEM certificate");
  }
  EXPECT_THROW(ReadCertificateSubject("/nonexistent/cert.pem"), Error);
}

TEST(ParticipantIdentityTest, IsTheGuidPrefixAsSubjectFingerprintDashParticipant) {
  dds_guid_t guid{};
  for (int i = 0; i < 16; ++i) guid.v[i] = static_cast<uint8_t>(0x10 * (i % 16) + i);
  EXPECT_EQ(ParticipantIdentity(guid), "001122334455-66778899aabb");
}

}  // namespace
}  // namespace flsd::dds
