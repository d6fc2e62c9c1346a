//! The view's HTTP/1.1 transport: a listener that bounds what clients can hold, and one
//! request per connection.
//!
//! Why not a server crate: the view needs a handful of fixed endpoints, one request per
//! connection and hard bounds on what a client can tie up. `tiny_http` (a thread per
//! connection, unbounded, with no read deadline) lets idle or slowly-sending connections
//! pile up threads for ever; the async servers (hyper, axum) bring a runtime the synchronous
//! renderer does not need. So the connection handling is this module's own, over
//! `std::net`, and the request head is parsed by `httparse` (the parser hyper uses).
//!
//! Bounds: at most [`Limits::connections`] connections are open at once (one more is told
//! 503 and closed at once); a request's head and body must arrive within
//! [`Limits::request_deadline`] of the connection's opening (a client that sends nothing, or
//! sends slowly, is closed then); the head is at most [`Limits::head_bytes`], the body at most
//! [`Limits::body_bytes`]; a response that the client does not read is dropped after
//! [`Limits::write_timeout`]. Every response closes its connection.

use std::io::{Read, Write};
use std::net::{SocketAddr, TcpListener, TcpStream};
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use crate::error::{Error, Result};

/// What one client may hold of the server.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Limits {
    /// Connections open at once.
    pub connections: usize,
    /// Time from a connection's opening by which its whole request must have arrived.
    pub request_deadline: Duration,
    /// Largest request head (request line and headers), bytes.
    pub head_bytes: usize,
    /// Largest request body, bytes.
    pub body_bytes: usize,
    /// Longest wait for a client to take a response's bytes.
    pub write_timeout: Duration,
}

/// The request method, as far as the view distinguishes it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub(crate) enum Method {
    /// `GET`.
    Get,
    /// `POST`.
    Post,
    /// Anything else (named).
    Other(String),
}

/// One parsed request.
#[derive(Clone, Debug)]
pub(crate) struct Request {
    /// Its method.
    pub method: Method,
    /// The request target as sent (path and query).
    pub target: String,
    /// The `Host` header, if one was sent.
    pub host: Option<String>,
    /// The body (empty without `Content-Length`).
    pub body: Vec<u8>,
}

/// One response: status, content type, extra headers and body.
#[derive(Clone, Debug)]
pub(crate) struct Response {
    /// HTTP status code.
    pub status: u16,
    /// `Content-Type`.
    pub content_type: String,
    /// Further headers (ASCII names and values).
    pub headers: Vec<(String, String)>,
    /// The body.
    pub body: Vec<u8>,
}

impl Response {
    /// A response of `status` with `body` of type `content_type`.
    pub(crate) fn new(status: u16, content_type: &str, body: Vec<u8>) -> Response {
        Response {
            status,
            content_type: content_type.to_string(),
            headers: Vec::new(),
            body,
        }
    }

    /// This response with header `name: value` added.
    pub(crate) fn with_header(mut self, name: &str, value: impl Into<String>) -> Response {
        self.headers.push((name.to_string(), value.into()));
        self
    }
}

/// A bound listener with its [`Limits`].
pub(crate) struct HttpServer {
    listener: TcpListener,
    limits: Limits,
    open: Arc<AtomicUsize>,
}

/// Why a request could not be read: answered with this status, or (`None`) closed unanswered.
struct Unreadable(Option<(u16, &'static str)>);

impl HttpServer {
    /// Listens on `addr` (port 0: any free port).
    pub(crate) fn bind(addr: SocketAddr, limits: Limits) -> Result<HttpServer> {
        let listener = TcpListener::bind(addr)
            .map_err(|e| Error::Invalid(format!("cannot listen on {addr}: {e}")))?;
        Ok(HttpServer {
            listener,
            limits,
            open: Arc::new(AtomicUsize::new(0)),
        })
    }

    /// The address bound, with the port chosen when 0 was asked for.
    pub(crate) fn local_addr(&self) -> Result<SocketAddr> {
        self.listener
            .local_addr()
            .map_err(|e| Error::Invalid(format!("the listening address: {e}")))
    }

    /// Accepts connections until the listener fails, answering each connection's one request
    /// with `handler` on a thread of its own (at most [`Limits::connections`] at once).
    pub(crate) fn serve<H>(&self, handler: Arc<H>)
    where
        H: Fn(Request) -> Response + Send + Sync + 'static,
    {
        for stream in self.listener.incoming() {
            let Ok(stream) = stream else {
                // A connection that failed while being accepted (reset by its client) is
                // that client's loss only.
                continue;
            };
            let opened = Instant::now();
            if self.open.fetch_add(1, Ordering::SeqCst) >= self.limits.connections {
                self.open.fetch_sub(1, Ordering::SeqCst);
                let busy = Response::new(503, "text/plain", b"too many connections\n".to_vec());
                let _ = stream.set_write_timeout(Some(Duration::from_millis(100)));
                let _ = write_response(&stream, &busy);
                continue;
            }
            let (open, limits, handler) = (self.open.clone(), self.limits, handler.clone());
            let spawned = std::thread::Builder::new()
                .name("view-connection".into())
                .spawn(move || {
                    serve_connection(stream, opened, &limits, &*handler);
                    open.fetch_sub(1, Ordering::SeqCst);
                });
            if spawned.is_err() {
                // No thread for it: the connection was dropped (closed) with the closure.
                self.open.fetch_sub(1, Ordering::SeqCst);
            }
        }
    }
}

/// Reads the one request of `stream`, answers it and closes the connection.
fn serve_connection<H>(stream: TcpStream, opened: Instant, limits: &Limits, handler: &H)
where
    H: Fn(Request) -> Response,
{
    let _ = stream.set_write_timeout(Some(limits.write_timeout));
    let response = match read_request(&stream, opened, limits) {
        Ok(request) => handler(request),
        Err(Unreadable(Some((status, why)))) => {
            Response::new(status, "text/plain", format!("{why}\n").into_bytes())
        }
        Err(Unreadable(None)) => return,
    };
    let _ = write_response(&stream, &response);
    let _ = stream.shutdown(std::net::Shutdown::Write);
}

/// Reads from `stream` into `buf` until `done(buf)` holds, the deadline passes or `cap`
/// bytes are held.
fn read_until(
    mut stream: &TcpStream,
    buf: &mut Vec<u8>,
    deadline: Instant,
    cap: usize,
    done: impl Fn(&[u8]) -> bool,
) -> std::result::Result<(), Unreadable> {
    let mut chunk = [0u8; 8192];
    while !done(buf) {
        if buf.len() >= cap {
            return Err(Unreadable(Some((431, "request head or body too large"))));
        }
        let left = deadline.saturating_duration_since(Instant::now());
        if left.is_zero() || stream.set_read_timeout(Some(left)).is_err() {
            return Err(Unreadable(Some((
                408,
                "the request did not arrive in time",
            ))));
        }
        match stream.read(&mut chunk[..(cap - buf.len()).min(8192)]) {
            Ok(0) => return Err(Unreadable(None)),
            Ok(n) => buf.extend_from_slice(&chunk[..n]),
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
            Err(e)
                if matches!(
                    e.kind(),
                    std::io::ErrorKind::WouldBlock | std::io::ErrorKind::TimedOut
                ) =>
            {
                return Err(Unreadable(Some((
                    408,
                    "the request did not arrive in time",
                ))));
            }
            Err(_) => return Err(Unreadable(None)),
        }
    }
    Ok(())
}

/// The end of the head in `buf` (the index after `\r\n\r\n`).
fn head_end(buf: &[u8]) -> Option<usize> {
    buf.windows(4)
        .position(|w| w == b"\r\n\r\n")
        .map(|at| at + 4)
}

/// Reads and parses one request within `limits`.
fn read_request(
    stream: &TcpStream,
    opened: Instant,
    limits: &Limits,
) -> std::result::Result<Request, Unreadable> {
    let deadline = opened + limits.request_deadline;
    let mut buf = Vec::new();
    read_until(stream, &mut buf, deadline, limits.head_bytes, |b| {
        head_end(b).is_some()
    })
    .map_err(|e| match e {
        Unreadable(Some((431, _))) => Unreadable(Some((431, "request head too large"))),
        other => other,
    })?;
    let end = head_end(&buf).unwrap_or(buf.len());
    let mut headers = [httparse::EMPTY_HEADER; 32];
    let mut parsed = httparse::Request::new(&mut headers);
    match parsed.parse(&buf[..end]) {
        Ok(httparse::Status::Complete(_)) => {}
        Ok(httparse::Status::Partial) | Err(_) => {
            return Err(Unreadable(Some((400, "malformed request"))));
        }
    }
    let method = match parsed.method.unwrap_or("") {
        "GET" => Method::Get,
        "POST" => Method::Post,
        other => Method::Other(other.to_string()),
    };
    let target = parsed.path.unwrap_or("").to_string();
    let header = |name: &str| {
        parsed
            .headers
            .iter()
            .find(|h| h.name.eq_ignore_ascii_case(name))
            .map(|h| String::from_utf8_lossy(h.value).trim().to_string())
    };
    if header("Transfer-Encoding").is_some() {
        return Err(Unreadable(Some((
            411,
            "send the body with a Content-Length, not chunked",
        ))));
    }
    let length = match header("Content-Length") {
        None => 0,
        Some(v) => v
            .parse::<usize>()
            .map_err(|_| Unreadable(Some((400, "malformed Content-Length"))))?,
    };
    if length > limits.body_bytes {
        return Err(Unreadable(Some((413, "request body too large"))));
    }
    let host = header("Host");
    let mut body = buf.split_off(end);
    read_until(stream, &mut body, deadline, length, |b| b.len() >= length)?;
    body.truncate(length);
    Ok(Request {
        method,
        target,
        host,
        body,
    })
}

/// The reason phrase of `status`.
fn reason(status: u16) -> &'static str {
    match status {
        200 => "OK",
        204 => "No Content",
        400 => "Bad Request",
        403 => "Forbidden",
        404 => "Not Found",
        405 => "Method Not Allowed",
        408 => "Request Timeout",
        411 => "Length Required",
        413 => "Content Too Large",
        414 => "URI Too Long",
        422 => "Unprocessable Content",
        431 => "Request Header Fields Too Large",
        500 => "Internal Server Error",
        503 => "Service Unavailable",
        _ => "",
    }
}

/// Writes `response` with its length and `Connection: close`.
fn write_response(mut stream: &TcpStream, response: &Response) -> std::io::Result<()> {
    let mut head = format!(
        "HTTP/1.1 {} {}\r\nContent-Type: {}\r\nContent-Length: {}\r\nConnection: close\r\n",
        response.status,
        reason(response.status),
        response.content_type,
        response.body.len()
    );
    for (name, value) in &response.headers {
        // Only ASCII without line breaks can be a header; anything else is left out.
        if name
            .bytes()
            .chain(value.bytes())
            .all(|b| b.is_ascii() && b >= b' ')
        {
            head += &format!("{name}: {value}\r\n");
        }
    }
    head += "\r\n";
    stream.write_all(head.as_bytes())?;
    stream.write_all(&response.body)?;
    stream.flush()
}

/// Test-only items: used by the unit tests of this and other modules, compiled only for them.
#[cfg(test)]
pub(crate) mod test_support {
    use super::*;

    impl HttpServer {
        /// Connections open now.
        pub(crate) fn open_connections(&self) -> usize {
            self.open.load(Ordering::SeqCst)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn limits() -> Limits {
        Limits {
            connections: 3,
            request_deadline: Duration::from_millis(400),
            head_bytes: 1024,
            body_bytes: 64,
            write_timeout: Duration::from_secs(5),
        }
    }

    /// A server on a free loopback port answering with the request's method, target and body.
    fn echo() -> (Arc<HttpServer>, SocketAddr) {
        let server = Arc::new(
            HttpServer::bind("127.0.0.1:0".parse().expect("address"), limits()).expect("bind"),
        );
        let addr = server.local_addr().expect("address");
        let me = server.clone();
        std::thread::spawn(move || {
            me.serve(Arc::new(|r: Request| {
                let text = format!(
                    "{:?} {} {:?} {}",
                    r.method,
                    r.target,
                    r.host,
                    String::from_utf8_lossy(&r.body)
                );
                Response::new(200, "text/plain", text.into_bytes()).with_header("X-A", "1")
            }))
        });
        (server, addr)
    }

    fn exchange(addr: SocketAddr, request: &[u8]) -> String {
        let mut stream = TcpStream::connect(addr).expect("connect");
        stream
            .set_read_timeout(Some(Duration::from_secs(10)))
            .expect("timeout");
        let _ = stream.write_all(request);
        let mut answer = Vec::new();
        let _ = stream.read_to_end(&mut answer);
        String::from_utf8_lossy(&answer).into_owned()
    }

    fn wait_until(what: impl Fn() -> bool) {
        let start = Instant::now();
        while !what() {
            assert!(start.elapsed() < Duration::from_secs(10), "never happened");
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    #[test]
    fn a_request_is_parsed_and_answered_with_its_length() {
        let (_server, addr) = echo();
        let answer = exchange(
            addr,
            b"POST /view?token=1 HTTP/1.1\r\nHost: h:1\r\nContent-Length: 5\r\n\r\nhello",
        );
        assert!(answer.starts_with("HTTP/1.1 200 OK\r\n"), "{answer}");
        assert!(answer.contains("Connection: close\r\n"), "{answer}");
        assert!(answer.contains("X-A: 1\r\n"), "{answer}");
        let body = "Post /view?token=1 Some(\"h:1\") hello";
        assert!(
            answer.contains(&format!("Content-Length: {}\r\n", body.len())),
            "{answer}"
        );
        assert!(answer.ends_with(body), "{answer}");
    }

    #[test]
    fn oversized_malformed_and_chunked_requests_are_refused() {
        let (_server, addr) = echo();
        let long = format!("GET /{} HTTP/1.1\r\n\r\n", "a".repeat(2000));
        for (request, status) in [
            (long.as_bytes(), 431),
            (
                b"GET / HTTP/1.1\r\nContent-Length: 65\r\n\r\n".as_slice(),
                413,
            ),
            (b"GET / HTTP/1.1\r\nContent-Length: x\r\n\r\n", 400),
            (b"GET / HTTP/1.1\r\nTransfer-Encoding: chunked\r\n\r\n", 411),
            (b"\x01\x02 garbage\r\n\r\n", 400),
        ] {
            let answer = exchange(addr, request);
            assert!(
                answer.starts_with(&format!("HTTP/1.1 {status} ")),
                "{status}: {answer}"
            );
        }
    }

    /// Idle connections hold at most the cap: one more is refused at once, each is closed at
    /// the request deadline, and then the server answers again.
    #[test]
    fn idle_connections_are_capped_and_closed_at_the_deadline() {
        let (server, addr) = echo();
        let idle: Vec<TcpStream> = (0..3)
            .map(|_| TcpStream::connect(addr).expect("connect"))
            .collect();
        wait_until(|| server.open_connections() == 3);
        // A full request, refused unread: served, it would be answered 200.
        let refused = exchange(addr, b"GET / HTTP/1.1\r\n\r\n");
        assert!(refused.starts_with("HTTP/1.1 503 "), "{refused}");
        for mut stream in idle {
            let mut answer = String::new();
            let _ = stream.read_to_string(&mut answer);
            assert!(answer.starts_with("HTTP/1.1 408 "), "{answer}");
        }
        wait_until(|| server.open_connections() == 0);
        let answer = exchange(addr, b"GET /again HTTP/1.1\r\n\r\n");
        assert!(answer.ends_with("Get /again None "), "{answer}");
    }

    /// A client that sends its head a byte at a time cannot keep the connection beyond the
    /// deadline.
    #[test]
    fn a_slow_client_is_closed_at_the_deadline() {
        let (_server, addr) = echo();
        let mut stream = TcpStream::connect(addr).expect("connect");
        let start = Instant::now();
        let mut closed = false;
        for b in b"GET / HTTP/1.1\r\nX-Slow: ".iter().cycle().take(200) {
            if stream.write_all(&[*b]).is_err() {
                closed = true;
                break;
            }
            std::thread::sleep(Duration::from_millis(20));
            if start.elapsed() > Duration::from_secs(2) {
                break;
            }
        }
        let mut answer = String::new();
        let _ = stream.read_to_string(&mut answer);
        assert!(
            closed || answer.starts_with("HTTP/1.1 408 "),
            "{closed} {answer}"
        );
        assert!(start.elapsed() < Duration::from_secs(2), "closed in time");
    }
}
