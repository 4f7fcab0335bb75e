#!/usr/bin/env python3
"""A fault-injecting HTTP/1.1 proxy for Parallax's network tests (loopback only).

Sits between the client and a real server (nginx) and spoils some answers on purpose:

  pass          forwards every answer as it is
  delay         waits --delay-ms before answering
  drop          sends the headers and half the body, then closes the connection
  503           answers 503 Service Unavailable (Retry-After: --retry-after, default 0)
  404           answers 404 Not Found
  truncate      sends half the body with a Content-Length that says so (Content-Range unchanged)
  ignore-range  asks upstream without Range and answers 200 with the whole file
  etag          rewrites the ETag to another value (the file "changed on the server")
  no-validators forwards the answer without its ETag and Last-Modified (a server that states
                no version of the file)
  stall         sends nothing for --delay-ms, then closes
  trickle       sends the headers, then the body one byte every --delay-ms

Which requests: those whose path ends with --path-suffix (default: all), after the first
--after of them, every --every'th (1: each), the same request (path and Range) at most
--times-per-request times, and at most --max-faults in all (a flaky network: with more attempts
than faults, every range gets through in the end, however requests are merged). Requests in absolute form ("GET http://host/...",
as a client sends them to a proxy named by http_proxy) go to the host they name; the others to
--upstream. Every request is logged to --log: "index path range status action".

Prints "PORT <n>" on stdout once listening (port 0 picks a free one). Standard library only.
"""

import argparse
import http.client
import http.server
import socket
import sys
import threading
import time
import urllib.parse

HOP_HEADERS = {"connection", "keep-alive", "proxy-connection", "transfer-encoding", "te",
               "trailer", "upgrade", "proxy-authorization", "proxy-authenticate"}


def parse_args():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--upstream", required=True, help="host:port of the real server")
    parser.add_argument("--port", type=int, default=0)
    parser.add_argument("--mode", default="pass",
                        choices=["pass", "delay", "drop", "503", "404", "truncate",
                                 "ignore-range", "etag", "no-validators", "stall",
                                 "trickle"])
    parser.add_argument("--path-suffix", default="")
    parser.add_argument("--after", type=int, default=0)
    parser.add_argument("--every", type=int, default=1)
    parser.add_argument("--times-per-request", type=int, default=0, help="0: no limit")
    parser.add_argument("--max-faults", type=int, default=0, help="0: no limit")
    parser.add_argument("--delay-ms", type=int, default=0)
    parser.add_argument("--retry-after", default="0", help="the 503 answers' Retry-After")
    parser.add_argument("--log", required=True)
    return parser.parse_args()


class Faults:
    def __init__(self, args):
        self.args = args
        self.lock = threading.Lock()
        self.matched = 0
        self.index = 0
        self.faulted = {}  # (path, range) -> times faulted
        self.faults = 0
        self.log = open(args.log, "a", buffering=1)

    def decide(self, path, range_header):
        """The request's index, and whether the fault applies to it."""
        with self.lock:
            self.index += 1
            index = self.index
            if not path.endswith(self.args.path_suffix):
                return index, False
            self.matched += 1
            k = self.matched - self.args.after
            if k <= 0 or k % self.args.every != 0:
                return index, False
            key = (path, range_header)
            limit = self.args.times_per_request
            if limit > 0 and self.faulted.get(key, 0) >= limit:
                return index, False
            if self.args.max_faults > 0 and self.faults >= self.args.max_faults:
                return index, False
            self.faulted[key] = self.faulted.get(key, 0) + 1
            self.faults += 1
            return index, True

    def write(self, index, path, range_header, status, action):
        with self.lock:
            self.log.write(f"{index} {path} {range_header or '-'} {status} {action}\n")


def make_handler(faults, args):
    up_host, up_port = args.upstream.rsplit(":", 1)

    class Handler(http.server.BaseHTTPRequestHandler):
        protocol_version = "HTTP/1.1"

        def log_message(self, format, *values):  # quiet: the log file has what matters
            pass

        def do_HEAD(self):
            self.handle_get(head=True)

        def do_GET(self):
            self.handle_get(head=False)

        def handle_get(self, head):
            target = self.path
            host, port = up_host, int(up_port)
            if target.startswith("http://"):
                parsed = urllib.parse.urlsplit(target)
                host, port = parsed.hostname, parsed.port or 80
                target = parsed.path + ("?" + parsed.query if parsed.query else "")
            path = target.split("?", 1)[0]
            range_header = self.headers.get("Range")
            index, fault = faults.decide(path, range_header)
            mode = args.mode if fault else "pass"

            if mode == "stall":
                faults.write(index, path, range_header, 0, "stall")
                time.sleep(args.delay_ms / 1000.0)
                self.close_connection = True
                return
            if mode in ("503", "404"):
                status = int(mode)
                body = b"fault injected\n"
                # Logged before the answer goes out: a client that has it finds it in the log.
                faults.write(index, path, range_header, status, mode)
                self.send_response(status)
                self.send_header("Content-Length", str(len(body)))
                if status == 503:
                    self.send_header("Retry-After", args.retry_after)
                self.end_headers()
                if not head:
                    self.wfile.write(body)
                return

            headers = {}
            for name, value in self.headers.items():
                if name.lower() in HOP_HEADERS or name.lower() == "host":
                    continue
                if mode == "ignore-range" and name.lower() in ("range", "if-none-match",
                                                               "if-modified-since", "if-range"):
                    continue
                headers[name] = value
            connection = http.client.HTTPConnection(host, port, timeout=30)
            try:
                connection.request("HEAD" if head else "GET", target, headers=headers)
                answer = connection.getresponse()
                body = answer.read()
                status = answer.status
                answer_headers = [(n, v) for n, v in answer.getheaders()
                                  if n.lower() not in HOP_HEADERS]
            finally:
                connection.close()

            if mode == "delay":
                time.sleep(args.delay_ms / 1000.0)
            if mode == "etag":
                answer_headers = [(n, '"changed-on-the-server"' if n.lower() == "etag" else v)
                                  for n, v in answer_headers]
            if mode == "no-validators":
                answer_headers = [(n, v) for n, v in answer_headers
                                  if n.lower() not in ("etag", "last-modified")]
            send_body = body
            declared = len(body)
            if mode == "truncate":
                send_body = body[: len(body) // 2]
                declared = len(send_body)
            faults.write(index, path, range_header, status, mode)
            self.send_response(status)
            for name, value in answer_headers:
                if name.lower() == "content-length":
                    continue
                self.send_header(name, value)
            self.send_header("Content-Length", str(declared))
            self.end_headers()
            if head:
                return
            if mode == "drop":
                self.wfile.write(send_body[: len(send_body) // 2])
                self.wfile.flush()
                # An abrupt end: the client sees the connection close mid-body.
                try:
                    self.connection.shutdown(socket.SHUT_RDWR)
                except OSError:
                    pass
                self.close_connection = True
                return
            if mode == "trickle":
                try:
                    for i in range(len(send_body)):
                        self.wfile.write(send_body[i:i + 1])
                        self.wfile.flush()
                        time.sleep(args.delay_ms / 1000.0)
                except OSError:
                    pass  # the client gave up: what the test expects
                self.close_connection = True
                return
            self.wfile.write(send_body)

    return Handler


def main():
    args = parse_args()
    faults = Faults(args)
    server = http.server.ThreadingHTTPServer(("127.0.0.1", args.port), make_handler(faults, args))
    server.daemon_threads = True
    print(f"PORT {server.server_address[1]}", flush=True)
    try:
        server.serve_forever()
    except KeyboardInterrupt:
        pass
    return 0


if __name__ == "__main__":
    sys.exit(main())
