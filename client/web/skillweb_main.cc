// skillweb: the live view of a robot in a browser. A DDS client of skilld like skillctl (skilld
// itself serves no web page and writes no JSON) that serves one page, streams the state topic to
// it and passes the page's motion calls on. docs/skillweb.md describes it.

#include <CLI/CLI.hpp>

#include <cstdio>
#include <exception>

#include "client/client.h"
#include "client/web/http_server.h"
#include "client/web/web_app.h"
#include "core/check.h"
#include "core/config.h"
#include "core/paths.h"
#include "core/signals.h"

int main(int argc, char** argv) {
  flsd::BlockTerminationSignals();
  CLI::App app{"skillweb: skilld's live view and controls in a browser"};
  flsd::Client::Options client;
  std::string host = "127.0.0.1", map = "configs/maps/demo.yaml";
  std::string page_dir = FLSD_WEB_PAGE_DIR, urdf = "robot/a1/a1.urdf", security_file;
  int port = 8090;
  app.add_option("--domain", client.domain_id, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--partition", client.partition, "DDS partition");
  app.add_option("--client-id", client.client_id,
                 "Client id (default: host-pid-random; with --security, this participant's identity)");
  app.add_option("--security", security_file,
                 "DDS Security: a YAML file with a security: section (scripts/make_pki.sh writes one per identity)");
  app.add_option("--host", host, "Address to serve the page on (0.0.0.0: every interface, for a phone)");
  app.add_option("--port", port, "HTTP port; 0: any free one (printed)")->check(CLI::Range(0, 65535));
  app.add_option("--map", map, "Navigation map shown on the page (YAML; the server's default); '' for none");
  app.add_option("--page-dir", page_dir, "The built page (index.html, app.js, style.css)");
  app.add_option("--urdf", urdf, "The robot's URDF");
  CLI11_PARSE(app, argc, argv);

  try {
    flsd::web::WebAppOptions options;
    options.page_dir = page_dir;
    options.urdf_path = flsd::ResolveDataPath(urdf);
    if (!map.empty()) options.map = flsd::Map2D::Load(map);
    options.loopback_only = host.rfind("127.", 0) == 0;
    if (!security_file.empty()) {
      client.security = flsd::LoadConfigSection<flsd::dds::SecurityConfig>(security_file, "security");
      const std::string error = flsd::dds::SecurityFilesError(client.security, security_file + ":");
      if (!error.empty()) throw flsd::InputError(error);
    }
    flsd::Client dds(client);
    flsd::web::WebApp web(dds, options);
    flsd::web::HttpServer server(host, port, [&web](const flsd::web::HttpRequest& r) { return web.Handle(r); });
    std::printf("skillweb: http://%s:%d/ (client %s)\n", host.c_str(), server.port(), dds.id().c_str());
    std::fflush(stdout);
    flsd::WaitForTermination();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "skillweb: %s\n", e.what());
    return 1;
  }
  return 0;
}
