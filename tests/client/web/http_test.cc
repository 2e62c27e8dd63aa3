// skillweb's HTTP server over a real socket, and the routes' checks that need no skilld: which
// requests are refused before anything reaches the robot.

#include <gtest/gtest.h>

#include "client/web/http_server.h"
#include "client/web/web_app.h"
#include "tests/client/web/http_exchange.h"
#include "tests/common/dds_support.h"
#include "tests/common/test_support.h"

namespace flsd::web {
namespace {

using testutil::HttpExchange;

TEST(HttpRequestTest, ParsesTheRequestLineAndHeaders) {
  HttpRequest r;
  ASSERT_TRUE(ParseRequestHead("POST /api/stand?x=1 HTTP/1.1\r\nHost: 127.0.0.1:8090\r\nContent-Type:  application/json \r", r));
  EXPECT_EQ(r.method, "POST");
  EXPECT_EQ(r.path, "/api/stand");
  EXPECT_EQ(r.query, "x=1");
  EXPECT_EQ(r.Header("host"), "127.0.0.1:8090");
  EXPECT_EQ(r.Header("content-type"), "application/json");
  HttpRequest bad;
  EXPECT_FALSE(ParseRequestHead("GET / SPDY/3\r", bad));
  EXPECT_FALSE(ParseRequestHead("GET nopath HTTP/1.1\r", bad));
  EXPECT_FALSE(ParseRequestHead("GET / HTTP/1.1\r\nno colon here\r", bad));
}

TEST(HttpServerTest, AnswersAndStreamsOverASocket) {
  HttpServer server("127.0.0.1", 0, [](const HttpRequest& r) {
    if (r.path == "/stream") {
      HttpResponse s;
      s.content_type = "text/event-stream";
      s.stream = [](HttpStream& out) {
        for (int i = 0; i < 3; ++i) out.Write("data: " + std::to_string(i) + "\n\n");
      };
      return s;
    }
    return HttpResponse::Json(200, "{\"body\":\"" + r.body + "\"}");
  });
  ASSERT_GT(server.port(), 0);
  const std::string reply = HttpExchange(server.port(), "POST /x HTTP/1.1\r\nHost: a\r\nContent-Length: 5\r\n\r\nhello");
  EXPECT_EQ(reply.rfind("HTTP/1.1 200 OK\r\n", 0), 0u) << reply;
  EXPECT_NE(reply.find("Content-Length: 16\r\n"), std::string::npos) << reply;
  EXPECT_NE(reply.find("\r\n\r\n{\"body\":\"hello\"}"), std::string::npos) << reply;

  const std::string stream = HttpExchange(server.port(), "GET /stream HTTP/1.1\r\nHost: a\r\n\r\n");
  EXPECT_NE(stream.find("Content-Type: text/event-stream\r\n"), std::string::npos);
  EXPECT_NE(stream.find("\r\n\r\ndata: 0\n\ndata: 1\n\ndata: 2\n\n"), std::string::npos) << stream;
}

TEST(HttpServerTest, RefusesMalformedAndOversizedRequests) {
  int handled = 0;
  HttpServer server("127.0.0.1", 0, [&handled](const HttpRequest&) {
    ++handled;
    return HttpResponse::Text(200, "ok");
  });
  EXPECT_EQ(HttpExchange(server.port(), "hello\r\n\r\n").rfind("HTTP/1.1 400", 0), 0u);
  const std::string big = "POST / HTTP/1.1\r\nContent-Length: " + std::to_string(HttpServer::kMaxBodyBytes + 1) + "\r\n\r\n";
  EXPECT_EQ(HttpExchange(server.port(), big).rfind("HTTP/1.1 400", 0), 0u);
  // Headers past the limit: the connection is dropped (the answer may be lost in the reset).
  HttpExchange(server.port(), "GET / HTTP/1.1\r\n" + std::string(2 * HttpServer::kMaxHeaderBytes, 'x'));
  EXPECT_EQ(handled, 0);
}

TEST(HttpServerTest, ThrowsWhenItCannotListen) {
  EXPECT_THROW(HttpServer("not an address", 0, nullptr), std::runtime_error);
  HttpServer first("127.0.0.1", 0, nullptr);
  EXPECT_THROW(HttpServer("127.0.0.1", first.port(), nullptr), std::runtime_error);
}

// The routes with no server behind the client: only the refusals are answered without one.
class WebAppTest : public ::testing::Test {
 protected:
  void SetUp() override {
    testutil::UseLoopbackDds();
    Client::Options options;
    options.domain_id = testutil::TestDomainId();
    options.partition = testutil::TestPartition();
    client_ = std::make_unique<Client>(options);
    WebAppOptions web;
    web.page_dir = "/nonexistent";
    web.urdf_path = FLSD_SOURCE_DIR "/robot/a1/a1.urdf";
    app_ = std::make_unique<WebApp>(*client_, web);
  }

  HttpResponse Post(const std::string& path, const std::string& body, const std::string& content_type = "application/json",
                    const std::string& host = "127.0.0.1:8090", const std::string& origin = "") {
    HttpRequest r;
    r.method = "POST";
    r.path = path;
    r.body = body;
    r.headers = {{"host", host}, {"content-type", content_type}};
    if (!origin.empty()) r.headers["origin"] = origin;
    return app_->Handle(r);
  }
  HttpResponse Get(const std::string& path, const std::string& host = "localhost:8090") {
    HttpRequest r;
    r.method = "GET";
    r.path = path;
    r.headers = {{"host", host}};
    return app_->Handle(r);
  }

  std::unique_ptr<Client> client_;
  std::unique_ptr<WebApp> app_;
};

TEST_F(WebAppTest, RefusesOtherSitesAndHostNames) {
  // Another site's form (no JSON), another site's script, a rebound domain name.
  EXPECT_EQ(Post("/api/damp", "{}", "text/plain").status, 403);
  EXPECT_EQ(Post("/api/damp", "{}", "application/json", "127.0.0.1:8090", "http://example.com").status, 403);
  EXPECT_EQ(Post("/api/damp", "{}", "application/json", "example.com:8090", "http://example.com:8090").status, 403);
  EXPECT_EQ(Get("/a1.urdf", "example.com:8090").status, 403);
}

TEST_F(WebAppTest, RefusesUnknownCallsAndBadArguments) {
  EXPECT_EQ(Post("/api/self_destruct", "{}").status, 404);
  EXPECT_EQ(Post("/api/execute_skill", "{\"skill\": ").status, 400);
  EXPECT_EQ(Post("/api/execute_skill", "[1]").status, 400);
  EXPECT_EQ(Post("/api/execute_skill", "{\"duration\": 4}").status, 400);  // no skill
  EXPECT_EQ(Post("/api/navigate", "{\"x\": \"far\", \"y\": 0}").status, 400);
  EXPECT_EQ(Get("/etc/passwd").status, 404);
  EXPECT_EQ(Get("/../robot/a1/a1.urdf").status, 404);
}

TEST_F(WebAppTest, ServesTheUrdfAndInfo) {
  const HttpResponse urdf = Get("/a1.urdf");
  EXPECT_EQ(urdf.status, 200);
  EXPECT_NE(urdf.body.find("<robot name=\"a1\">"), std::string::npos);
  const HttpResponse info = Get("/api/info");
  EXPECT_EQ(info.status, 200);
  EXPECT_NE(info.body.find("\"FR_hip_joint\""), std::string::npos);
  EXPECT_NE(info.body.find("\"map\":null"), std::string::npos);
  EXPECT_EQ(Get("/").status, 404);  // no page built into /nonexistent
}

}  // namespace
}  // namespace flsd::web
