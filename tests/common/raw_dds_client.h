#pragma once
// A real skilld on loopback with fuzz::RawClient, an independent client over raw DDS, connected to it.

#include <gtest/gtest.h>

#include <chrono>
#include <memory>
#include <string>

#include "fuzz/raw_client.h"
#include "tests/common/skilld_fixture.h"

namespace flsd::testutil {

class RawSkilldFixture : public SkilldFixture {
 protected:
  void SetUp() override {
    SkilldFixture::SetUp();
    StartServer();
    raw_ = std::make_unique<fuzz::RawClient>(domain_, partition_);
    ASSERT_TRUE(raw_->WaitForServer(std::chrono::seconds(15))) << server_->Log();
  }

  // A request with the next id: ids from the wall clock, as the IDL asks of a client.
  fuzz::RawRequest Request(const std::string& client, const std::string& call) {
    fuzz::RawRequest r;
    r.client_id = client;
    r.request_id = ++next_id_;
    r.call = call;
    return r;
  }

  std::unique_ptr<fuzz::RawClient> raw_;
  uint64_t next_id_ = static_cast<uint64_t>(dds_time());
};

}  // namespace flsd::testutil
