// skillweb: the live view of a robot in a browser. A DDS client of skilld like skillctl (skilld
// itself serves no web page and writes no JSON) that serves one page, streams the state topic to
// it and passes the page's motion calls on; with --users, each logged-in page is a client of its
// own. docs/skillweb.md describes it.

#include <CLI/CLI.hpp>
#include <termios.h>
#include <unistd.h>

#include <cstdio>
#include <exception>
#include <iostream>

#include "client/client.h"
#include "client/web/credentials.h"
#include "client/web/page_agent.h"
#include "client/web/users_file.h"
#include "client/web/web_app.h"
#include "core/check.h"
#include "core/paths.h"
#include "core/signals.h"

namespace {

// A line from stdin; from a terminal, without echo.
std::string ReadSecretLine(const char* prompt) {
  termios saved{};
  const bool terminal = isatty(STDIN_FILENO) && tcgetattr(STDIN_FILENO, &saved) == 0;
  if (terminal) {
    std::fprintf(stderr, "%s", prompt);
    termios quiet = saved;
    quiet.c_lflag &= ~static_cast<tcflag_t>(ECHO);
    tcsetattr(STDIN_FILENO, TCSANOW, &quiet);
  }
  std::string line;
  std::getline(std::cin, line);
  if (terminal) {
    tcsetattr(STDIN_FILENO, TCSANOW, &saved);
    std::fprintf(stderr, "\n");
  }
  return line;
}

// skillweb --users FILE --add-user NAME --role ROLE [--identity ID]: the password from stdin.
void AddUser(const std::string& users_file, const std::string& name, const std::string& role, const std::string& identity) {
  if (users_file.empty()) throw flsd::InputError("--add-user needs --users FILE, the file to add the user to");
  const std::string error = flsd::web::UserFieldError(name, role, identity);
  if (!error.empty()) throw flsd::InputError("--add-user: " + error);
  const std::string password = ReadSecretLine(("password for " + name + ": ").c_str());
  if (isatty(STDIN_FILENO) && ReadSecretLine("again: ") != password) throw flsd::InputError("the passwords differ");
  if (password.size() < 8) throw flsd::InputError("--add-user: a password needs 8 characters or more");
  const flsd::web::Role r = role == "operator" ? flsd::web::Role::kOperator : flsd::web::Role::kObserver;
  flsd::web::SaveUser(users_file, {name, r, identity, flsd::web::HashPassword(password)});
  std::printf("skillweb: %s is a user (%s, identity %s) in %s\n", name.c_str(), role.c_str(), identity.c_str(),
              users_file.c_str());
}

}  // namespace

int main(int argc, char** argv) {
  flsd::BlockTerminationSignals();
  CLI::App app{"skillweb: skilld's live view and controls in a browser"};
  flsd::Client::Options client;
  flsd::web::ListenOptions listen;
  std::string map = "configs/maps/demo.yaml", page_dir = FLSD_WEB_PAGE_DIR, urdf = "robot/a1/a1.urdf";
  std::string security_file, users_file, pki_dir, add_user, role = "observer", identity = "-";
  bool insecure = false, page_agent = false, read_only = false;
  int session_minutes = 30;
  app.add_option("--domain", client.domain_id, "DDS domain id")->check(CLI::Range(0, 232));
  app.add_option("--partition", client.partition, "DDS partition");
  app.add_option("--client-id", client.client_id,
                 "Client id of the open page (default: host-pid-random; with --security, this participant's identity)");
  app.add_option("--security", security_file,
                 "DDS Security of the open page (no --users): a YAML file with a security: section (scripts/make_pki.sh)");
  app.add_option("--host", listen.host,
                 "Address to serve the page on; beyond loopback (0.0.0.0: every interface, for a phone) it needs "
                 "--tls-cert, --tls-key and --users, or --insecure");
  app.add_option("--port", listen.port, "HTTP(S) port; 0: any free one (printed)")->check(CLI::Range(0, 65535));
  app.add_option("--tls-cert", listen.tls_cert, "HTTPS: the server's certificate (PEM)");
  app.add_option("--tls-key", listen.tls_key, "HTTPS: its private key (PEM)");
  app.add_option("--users", users_file,
                 "Logins: the users file (NAME ROLE IDENTITY PASSWORD_HASH a line; --add-user writes it); each "
                 "logged-in page is a DDS client of its own");
  app.add_option("--pki", pki_dir,
                 "With --users, DDS Security: the folder of scripts/make_pki.sh, whose IDENTITY/security.yaml each "
                 "user's page uses");
  app.add_option("--session-minutes", session_minutes, "A login ends after this long without a request or open page")
      ->check(CLI::Range(1, 24 * 60));
  app.add_flag("--insecure", insecure, "Serve beyond loopback without HTTPS or logins: anyone reaching the port commands");
  app.add_option("--add-user", add_user, "Add (or replace) this user in --users, the password read from stdin, and exit");
  app.add_option("--role", role, "With --add-user: operator (watches and commands) or observer (watches)");
  app.add_option("--identity", identity, "With --add-user: the user's make_pki.sh identity name, '-' for none");
  // skillweb's own: each page's DDS client in a process of its own (client/web/page_agent.h).
  app.add_flag("--page-agent", page_agent)->group("");
  app.add_flag("--read-only", read_only)->group("");
  app.add_option("--map", map, "Navigation map shown on the page (YAML; the server's default); '' for none");
  app.add_option("--page-dir", page_dir, "The built page (index.html, app.js, style.css)");
  app.add_option("--urdf", urdf, "The robot's URDF");
  CLI11_PARSE(app, argc, argv);

  try {
    if (!add_user.empty()) {
      AddUser(users_file, add_user, role, identity);
      return 0;
    }
    if (!security_file.empty()) client.security = flsd::dds::LoadSecurityFile(security_file);
    if (page_agent) {
      client.read_only = read_only;
      return flsd::web::RunPageAgent(client);
    }
    const std::string exposure = flsd::web::ExposureError(listen, !users_file.empty(), insecure);
    if (!exposure.empty()) throw flsd::InputError(exposure);
    if (!pki_dir.empty() && users_file.empty()) throw flsd::InputError("--pki names each user's identity: it needs --users");
    if (!security_file.empty() && !users_file.empty()) {
      throw flsd::InputError("--security is the open page's identity; with --users each user's comes from --pki");
    }
    flsd::web::WebAppOptions options;
    options.page_dir = page_dir;
    options.urdf_path = flsd::ResolveDataPath(urdf);
    if (!map.empty()) options.map = flsd::Map2D::Load(map);
    if (!users_file.empty()) options.users = flsd::web::LoadUsers(users_file);
    options.pki_dir = pki_dir;
    options.sessions.idle = std::chrono::minutes(session_minutes);
    options.client = client;
    options.agent_program = flsd::ProgramPath();
    flsd::web::WebApp web(options);
    const int port = web.Listen(listen);
    const std::string who = options.users ? std::to_string(options.users->size()) + " users, a login per page"
                                          : "open page, client " + web.open_client_id();
    std::printf("skillweb: %s://%s:%d/ (%s)\n", listen.tls() ? "https" : "http", listen.host.c_str(), port, who.c_str());
    std::fflush(stdout);
    flsd::WaitForTermination();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "skillweb: %s\n", e.what());
    return 1;
  }
  return 0;
}
