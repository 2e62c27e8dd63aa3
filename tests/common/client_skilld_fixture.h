#pragma once
// A real skilld (SkilldFixture) and flsd::Client connections to it.

#include <chrono>
#include <memory>

#include "client/client.h"
#include "tests/common/skilld_fixture.h"

namespace flsd::testutil {

class ClientSkilldFixture : public SkilldFixture {
 protected:
  // A client on the test's domain and partition, once it sees the server.
  std::unique_ptr<Client> Connect(std::chrono::milliseconds heartbeat = std::chrono::milliseconds(250)) {
    Client::Options options;
    options.domain_id = domain_;
    options.partition = partition_;
    options.heartbeat = heartbeat;
    auto client = std::make_unique<Client>(options);
    EXPECT_TRUE(client->WaitForServer(std::chrono::seconds(15))) << server_->Log();
    return client;
  }
};

}  // namespace flsd::testutil
