#include <sys/stat.h>

#include <cerrno>
#include <cstring>

#include <utility>  // before Asio: Boost 1.74 awaitable.hpp uses std::exchange without it

#include <boost/asio/ssl.hpp>
#include <fmt/format.h>
#include <openssl/ssl.h>

#include "access/access.hpp"

namespace spinewatch {

namespace ssl = boost::asio::ssl;

Status check_private_file(const std::filesystem::path& path, std::string_view key) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    return Error{fmt::format("{} {}: {}", key, path.string(), std::strerror(errno))};
  if (!S_ISREG(st.st_mode)) return Error{fmt::format("{} {}: not a regular file", key, path.string())};
  const unsigned mode = st.st_mode & 07777;
  if ((mode & 077) != 0)
    return Error{fmt::format("{} {}: mode {:04o} lets other users read a secret; chmod 600 {} (0600 or stricter)",
                             key, path.string(), mode, path.string())};
  return Ok{};
}

std::string Access::describe() const {
  std::vector<std::string> parts;
  if (tls) parts.push_back("TLS");
  if (client_certificates) parts.push_back("client certificates");
  if (tokens) parts.push_back(fmt::format("{} token{}", tokens->size(), tokens->size() == 1 ? "" : "s"));
  return parts.empty() ? "no TLS, no authentication" : fmt::format("{}", fmt::join(parts, ", "));
}

namespace {

// OpenSSL's error queue, as one phrase.
std::string openssl_error(const boost::system::system_error& e) { return e.code().message(); }

Result<std::shared_ptr<ssl::context>> tls_context(const AccessFiles& f, std::string_view section) {
  const std::string cert_key = fmt::format("{}.tls_cert", section), key_key = fmt::format("{}.tls_key", section),
                    ca_key = fmt::format("{}.tls_client_ca", section);
  if (auto ok = check_private_file(f.tls_key, key_key); !ok) return ok.error();
  auto context = std::make_shared<ssl::context>(ssl::context::tls_server);
  // TLS 1.2 and 1.3 only; no renegotiation by the client.
  context->set_options(ssl::context::default_workarounds | ssl::context::no_sslv2 | ssl::context::no_sslv3 |
                       ssl::context::no_tlsv1 | ssl::context::no_tlsv1_1 | ssl::context::single_dh_use);
  SSL_CTX_set_options(context->native_handle(), SSL_OP_NO_RENEGOTIATION);
  const std::string* where = &cert_key;
  const std::string* file = &f.tls_cert;
  try {
    context->use_certificate_chain_file(f.tls_cert);
    where = &key_key;
    file = &f.tls_key;
    context->use_private_key_file(f.tls_key, ssl::context::pem);
    if (SSL_CTX_check_private_key(context->native_handle()) != 1)
      return Error{fmt::format("{} {}: not the key of {} {}", key_key, f.tls_key, cert_key, f.tls_cert)};
    if (!f.tls_client_ca.empty()) {
      where = &ca_key;
      file = &f.tls_client_ca;
      context->load_verify_file(f.tls_client_ca);
      context->set_verify_mode(ssl::verify_peer | ssl::verify_fail_if_no_peer_cert);
      // The CA's name goes in the certificate request, so a client with several picks the right one.
      if (STACK_OF(X509_NAME)* names = SSL_load_client_CA_file(f.tls_client_ca.c_str()))
        SSL_CTX_set_client_CA_list(context->native_handle(), names);
    }
  } catch (const boost::system::system_error& e) {
    return Error{fmt::format("{} {}: {}", *where, *file, openssl_error(e))};
  }
  return context;
}

}  // namespace

Result<Access> load_access(const AccessFiles& f, std::string_view section) {
  Access access;
  if (f.tls_cert.empty() != f.tls_key.empty())
    return Error{fmt::format("{}.{}: set, but {}.{} is not: TLS needs the certificate and its key", section,
                             f.tls_cert.empty() ? "tls_key" : "tls_cert", section,
                             f.tls_cert.empty() ? "tls_cert" : "tls_key")};
  if (!f.tls_client_ca.empty() && f.tls_cert.empty())
    return Error{fmt::format("{}.tls_client_ca: client certificates need TLS: set {}.tls_cert and {}.tls_key",
                             section, section, section)};
  if (!f.tls_cert.empty()) {
    auto context = tls_context(f, section);
    if (!context) return context.error();
    access.tls = std::move(context).value();
    access.client_certificates = !f.tls_client_ca.empty();
  }
  if (!f.token_file.empty()) {
    auto tokens = TokenSet::load(f.token_file, fmt::format("{}.token_file", section));
    if (!tokens) return tokens.error();
    access.tokens = std::make_shared<const TokenSet>(std::move(tokens).value());
  }
  return access;
}

}  // namespace spinewatch
