#include "view/view_server.h"

#include "base/error.h"
#include "view/file_watcher.h"

#ifdef RAYCAST_HAVE_HTTPLIB

#include <httplib.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <pthread.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <arpa/inet.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>

#include "view/poll_one.h"

namespace raycast {

namespace {

// Requests are small and renders are what take time: enough workers keep the page, its status
// polls and an explain answered while images render, and while a few clients misbehave.
constexpr size_t kWorkers = 32;
// What one request may cost before it is answered 400 and its connection closed: the request
// line and headers within kMaxRequestBytes, all of it within kRequestMilliseconds. A connection
// that sends nothing is not even accepted (TCP_DEFER_ACCEPT: the kernel holds it until its first
// bytes arrive, or hands it over after kDeferSeconds, and then it is closed at once), and one
// idle between requests is closed after kKeepAliveMilliseconds. When more than half of the
// workers are busy, the server stops waiting for anyone: a request must arrive whole within
// kBusyMilliseconds (on loopback it takes well under one) and nothing is kept alive. So neither
// many connections nor slow ones can hold the workers for long or grow memory without bound.
constexpr size_t kMaxRequestBytes = 64 * 1024;
constexpr int kRequestMilliseconds = 2000;
constexpr int kBusyMilliseconds = 250;
constexpr int kDeferSeconds = 5;
constexpr int kKeepAliveMilliseconds = 2000;
constexpr int kKeepAliveRequests = 100;
constexpr size_t kMaxBodyBytes = 1024;  // the viewer's requests have no body

using Clock = std::chrono::steady_clock;


int milliseconds_until(Clock::time_point deadline) {
    const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(deadline - Clock::now()).count();
    return left > 0 ? static_cast<int>(left) : 0;
}

// Whether `events` (or a hang-up or error, which the next read or write reports) came on `socket`
// within `milliseconds`.
bool wait_for(int socket, short events, int milliseconds) {
    return (poll_one(socket, events, milliseconds) & (events | POLLHUP | POLLERR)) != 0;
}

// A connection's socket as httplib reads and writes it, with a budget: each request may read
// kMaxRequestBytes (its head and its small body) within kRequestSeconds.
class GuardedStream : public httplib::Stream {
public:
    explicit GuardedStream(int socket) : socket_(socket) {}

    void start_request(int milliseconds) {
        bytes_read_ = 0;
        deadline_ = Clock::now() + std::chrono::milliseconds(milliseconds);
        response_started_ = false;
        refused_ = false;
    }
    // Whether the answer to the last request was a 4xx or 5xx (other than 409, a cancelled
    // render): then the connection ends, and whoever sent a bad request gets no second try on it.
    bool refused() const { return refused_; }
    bool wait_for_request(int milliseconds) const { return wait_for(socket_, POLLIN, milliseconds); }

    bool is_readable() const override { return wait_for(socket_, POLLIN, milliseconds_until(deadline_)); }
    bool is_writable() const override { return wait_for(socket_, POLLOUT, kRequestMilliseconds); }
    ssize_t read(char* data, size_t size) override {
        if (bytes_read_ >= kMaxRequestBytes || !is_readable()) return -1;
        size = std::min(size, kMaxRequestBytes - bytes_read_);
        for (;;) {
            const ssize_t got = ::recv(socket_, data, size, 0);
            if (got < 0 && errno == EINTR) continue;
            if (got > 0) bytes_read_ += static_cast<size_t>(got);
            return got;
        }
    }
    ssize_t write(const char* data, size_t size) override {
        if (!response_started_ && size >= 12 && std::strncmp(data, "HTTP/1.1 ", 9) == 0) {
            response_started_ = true;
            refused_ = (data[9] == '4' || data[9] == '5') && std::strncmp(data + 9, "409", 3) != 0;
        }
        if (!is_writable()) return -1;
        for (;;) {
            const ssize_t sent = ::send(socket_, data, size, MSG_NOSIGNAL);
            if (sent < 0 && errno == EINTR) continue;
            return sent;
        }
    }
    void get_remote_ip_and_port(std::string& ip, int& port) const override { address_of(false, ip, port); }
    void get_local_ip_and_port(std::string& ip, int& port) const override { address_of(true, ip, port); }
    int socket() const override { return socket_; }

private:
    void address_of(bool local, std::string& ip, int& port) const {
        sockaddr_storage address{};
        socklen_t length = sizeof address;
        const int ok = local ? getsockname(socket_, reinterpret_cast<sockaddr*>(&address), &length)
                             : getpeername(socket_, reinterpret_cast<sockaddr*>(&address), &length);
        ip.clear();
        port = 0;
        if (ok != 0) return;
        char text[64] = "";
        if (address.ss_family == AF_INET) {
            const auto* in = reinterpret_cast<const sockaddr_in*>(&address);
            inet_ntop(AF_INET, &in->sin_addr, text, sizeof text);
            port = ntohs(in->sin_port);
        } else if (address.ss_family == AF_INET6) {
            const auto* in = reinterpret_cast<const sockaddr_in6*>(&address);
            inet_ntop(AF_INET6, &in->sin6_addr, text, sizeof text);
            port = ntohs(in->sin6_port);
        }
        ip = text;
    }

    int socket_;
    size_t bytes_read_ = 0;
    Clock::time_point deadline_ = Clock::now();
    bool response_started_ = false;
    bool refused_ = false;
};

// httplib's server with each connection read through a GuardedStream: the library parses,
// routes and answers; this bounds what a connection may cost.
class GuardedServer : public httplib::Server {
public:
    // httplib listens with a backlog of 5; connections that have not yet been accepted should
    // wait in the kernel's queue, not be refused, when many arrive at once.
    void deepen_backlog() { ::listen(svr_sock_, 1024); }

private:
    bool process_and_close_socket(socket_t socket) override {
        struct Busy {
            std::atomic<int>& count;
            explicit Busy(std::atomic<int>& c) : count(c) { ++count; }
            ~Busy() { --count; }
        } busy(busy_);
        GuardedStream stream(socket);
        bool closed = false;
        // The first request's bytes are already here (TCP_DEFER_ACCEPT), unless the kernel gave
        // up waiting for them.
        int wait = 0;
        for (int left = kKeepAliveRequests; left > 0 && !closed; --left) {
            const bool crowded = busy_.load() > static_cast<int>(kWorkers / 2);
            if (!stream.wait_for_request(crowded ? 0 : wait)) break;
            stream.start_request(crowded ? kBusyMilliseconds : kRequestMilliseconds);
            const bool last = left == 1 || crowded;
            if (!process_request(stream, last, closed, nullptr) || last || stream.refused()) break;
            wait = kKeepAliveMilliseconds;
        }
        ::shutdown(socket, SHUT_RDWR);
        ::close(socket);
        return true;
    }

    std::atomic<int> busy_{0};  // connections being served
};

void answer(httplib::Response& response, const ViewResponse& view) {
    response.status = view.status;
    response.set_content(view.body, view.content_type.c_str());
}

ViewResponse bad_query(const std::string& error) { return {400, "text/plain; charset=utf-8", error + "\n"}; }

const char* reason(int status) {
    switch (status) {
        case 400: return "bad request";
        case 404: return "not found: the viewer serves /, /image, /explain and /status";
        case 405: return "method not allowed: the viewer answers GET";
        case 413: return "request body too large: the viewer's requests have none";
        case 414: return "request URI too long";
        case 431: return "request headers too large";
        default: return "error";
    }
}

}  // namespace

bool view_server_available() { return true; }

void run_view_server(ViewSession& session, FileWatcher& files, const ViewServerOptions& options,
                     const std::function<void(const std::string& url)>& listening) {
    // SIGINT and SIGTERM go to one thread, which stops the server; every other thread (the
    // server's workers, the renderers) inherits the blocked mask.
    sigset_t stop_signals;
    sigemptyset(&stop_signals);
    sigaddset(&stop_signals, SIGINT);
    sigaddset(&stop_signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);

    GuardedServer server;
    server.new_task_queue = [] { return new httplib::ThreadPool(kWorkers); };
    server.set_payload_max_length(kMaxBodyBytes);
    server.set_socket_options([](socket_t socket) {
        int yes = 1;
        setsockopt(socket, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
        // Accept a connection only once it has sent something.
        int seconds = kDeferSeconds;
        setsockopt(socket, IPPROTO_TCP, TCP_DEFER_ACCEPT, &seconds, sizeof seconds);
    });
    server.set_default_headers({{"Cache-Control", "no-store"},
                                {"X-Content-Type-Options", "nosniff"},
                                {"Content-Security-Policy",
                                 "default-src 'none'; img-src 'self' blob: data:; style-src 'unsafe-inline'; "
                                 "script-src 'unsafe-inline'; connect-src 'self' blob:"}});
    server.set_pre_routing_handler([](const httplib::Request& request, httplib::Response& response) {
        // Every answer is whole: a Range header is ignored, as HTTP lets a server do. cpp-httplib
        // would cut the body to the ranges: 2,500 ranges in one 7.5 KB header multiplied an image
        // 2,500 times and killed the server with bad_alloc outside any handler (cpp-httplib issue
        // 1766, in Debian's 0.11), and one range went out as "200 OK" holding part of the image.
        // The request is the library's own non-const object, handed to this handler as const.
        const_cast<httplib::Request&>(request).ranges.clear();
        int status = 0;
        if (request.method != "GET" && request.method != "HEAD")
            status = 405;
        else if (request.has_header("Transfer-Encoding") ||
                 (request.has_header("Content-Length") && request.get_header_value("Content-Length") != "0"))
            status = 413;  // the viewer's requests have no body
        if (status == 0) return httplib::Server::HandlerResponse::Unhandled;
        response.status = status;
        response.set_header("Connection", "close");
        response.set_content(std::string(reason(status)) + "\n", "text/plain; charset=utf-8");
        return httplib::Server::HandlerResponse::Handled;
    });
    server.Get("/", [](const httplib::Request&, httplib::Response& response) {
        response.set_content(view_page_html(), "text/html; charset=utf-8");
    });
    server.Get("/status", [&session](const httplib::Request&, httplib::Response& response) {
        answer(response, session.status());
    });
    server.Get("/image", [&session](const httplib::Request& request, httplib::Response& response) {
        QueryParameters query;
        std::string error;
        answer(response, parse_query(request.target, query, error) ? session.image(query) : bad_query(error));
    });
    server.Get("/explain", [&session](const httplib::Request& request, httplib::Response& response) {
        QueryParameters query;
        std::string error;
        answer(response, parse_query(request.target, query, error) ? session.explain(query) : bad_query(error));
    });
    server.set_error_handler([](const httplib::Request&, httplib::Response& response) {
        if (response.body.empty())
            response.set_content(string_printf("%d %s\n", response.status, reason(response.status)),
                                 "text/plain; charset=utf-8");
    });

    server.set_exception_handler([](const httplib::Request&, httplib::Response& response, std::exception_ptr error) {
        std::string what = "internal error";
        try {
            std::rethrow_exception(error);
        } catch (const std::bad_alloc&) {
            what = "out of memory";
        } catch (const std::exception& e) {
            what = e.what();
        } catch (...) {
        }
        response.status = 500;
        response.set_content(what + "\n", "text/plain; charset=utf-8");
    });

    int port = options.port;
    if (port == 0) {
        port = server.bind_to_any_port(options.host);
        if (port < 0) throw InputError(options.host, "cannot listen on this address");
    } else if (!server.bind_to_port(options.host, port)) {
        throw InputError(string_printf("%s:%d", options.host.c_str(), port),
                         "cannot listen here: the port is in use, or the address is not this machine's");
    }

    server.deepen_backlog();
    std::atomic<bool> running{true};
    std::thread watcher([&] {
        // Every 200 ms the files are looked at anyway (see FileWatcher). A load that a save began
        // during is dropped: the next wait lets the writer finish, and the load after it shows the
        // save. A change found with no event heard waits for its event (a save just begun).
        while (running.load()) {
            files.watch(session.watched_files());
            files.wait(200);
            session.reload_if_changed([&](bool files_changed) { return files.changed_since_wait(files_changed); },
                                      [&] { return files.heard_of_change(); });
        }
    });
    std::thread stopper([&] {
        int signal = 0;
        sigwait(&stop_signals, &signal);
        server.stop();
    });
    const std::string host = options.host.find(':') != std::string::npos ? "[" + options.host + "]" : options.host;
    listening(string_printf("http://%s:%d/", host.c_str(), port));
    server.listen_after_bind();
    running = false;
    watcher.join();
    // If the server stopped by itself, wake the stopper.
    pthread_kill(stopper.native_handle(), SIGTERM);
    stopper.join();
}

}  // namespace raycast

#else

namespace raycast {

bool view_server_available() { return false; }

void run_view_server(ViewSession&, FileWatcher&, const ViewServerOptions&, const std::function<void(const std::string&)>&) {
    throw InputError("raycast view",
                     "this raycast was built without cpp-httplib, which the viewer needs: install it "
                     "(Debian/Ubuntu: sudo apt-get install libcpp-httplib-dev pkg-config) and rebuild");
}

}  // namespace raycast

#endif
