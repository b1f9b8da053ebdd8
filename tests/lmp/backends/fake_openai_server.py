"""A fake OpenAI-compatible chat endpoint that fails on purpose (a test double).

:class:`FakeOpenAIServer` listens on 127.0.0.1 (an ephemeral port) in a background thread and
answers ``POST .../chat/completions`` from a script of :class:`Reply` values, one per request;
the last reply repeats. Each reply is one behaviour of a real endpoint gone wrong: an answer
(``ok``), an answer too late (``hang``), an error status with an optional ``Retry-After``
(``status``), a body cut short by a closed connection (``cut``), a complete but truncated JSON
document (``truncated_json``), a 200 that is not JSON (``not_json``), JSON that is not a chat
completion (``wrong_shape``), a very long answer (``ok`` with long text), and a body that never
ends (``endless``: chunks sent until the client hangs up, fast or one every ``delay`` seconds).

Only the standard library is used, so the server stays independent of the client under test.
"""

from __future__ import annotations

import json
import threading
import time
from dataclasses import dataclass, field
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from types import TracebackType
from typing import Any, Literal

ReplyKind = Literal["ok", "hang", "status", "cut", "truncated_json", "not_json", "wrong_shape",
                    "endless"]

#: how long an endless body keeps going when nobody hangs up [s] (a safety net for the tests)
ENDLESS_LIMIT_S = 60.0


def chat_completion(text: str, finish_reason: str = "stop") -> dict[str, Any]:
    """A minimal valid chat completion answering ``text``."""
    return {
        "id": "chatcmpl-fake",
        "object": "chat.completion",
        "created": int(time.time()),
        "model": "fake-model",
        "choices": [{"index": 0, "message": {"role": "assistant", "content": text},
                     "finish_reason": finish_reason}],
        "usage": {"prompt_tokens": 7, "completion_tokens": 3, "total_tokens": 10},
    }


@dataclass(frozen=True)
class Reply:
    """One scripted answer.

    Attributes:
        kind: the behaviour (see the module doc).
        text: the completion's text ("ok", "hang").
        status: the HTTP status ("status").
        headers: extra response headers, e.g. ``{"Retry-After": "1"}``.
        delay: "hang": wait before answering [s]; "endless": pause between chunks [s].
    """

    kind: ReplyKind
    text: str = "ret_val = 1"
    status: int = 200
    headers: dict[str, str] = field(default_factory=dict)
    delay: float = 0.0

    @classmethod
    def ok(cls, text: str = "ret_val = 1") -> Reply:
        """A normal chat completion with ``text`` as the message content."""
        return cls("ok", text=text)

    @classmethod
    def hang(cls, seconds: float, text: str = "ret_val = 1") -> Reply:
        """Answer normally, but only after ``seconds`` [s] (longer than the client's timeout)."""
        return cls("hang", text=text, delay=seconds)

    @classmethod
    def error(cls, status: int, retry_after: str | None = None) -> Reply:
        """An OpenAI-style error body with ``status``; ``retry_after`` sets Retry-After."""
        headers = {} if retry_after is None else {"Retry-After": retry_after}
        return cls("status", status=status, headers=headers)

    @classmethod
    def endless(cls, delay: float = 0.0) -> Reply:
        """A 200 whose chunked body never ends; one chunk every ``delay`` [s]."""
        return cls("endless", delay=delay)


@dataclass(frozen=True)
class Received:
    """One request as the server saw it: its JSON body and when it arrived (monotonic [s])."""

    body: dict[str, Any]
    at: float


class FakeOpenAIServer:
    """The fake endpoint; use as a context manager (``with FakeOpenAIServer() as server``).

    Attributes:
        url: the API root to give the client, ``http://127.0.0.1:<port>/v1``.
        received: every request, in arrival order.
    """

    def __init__(self, *script: Reply) -> None:
        self._script: list[Reply] = list(script) or [Reply.ok()]
        self.received: list[Received] = []
        self._lock = threading.Lock()
        self._stop = threading.Event()
        self._httpd = ThreadingHTTPServer(("127.0.0.1", 0), _handler_for(self))
        self._httpd.daemon_threads = True
        self._thread = threading.Thread(target=self._httpd.serve_forever, daemon=True,
                                        name="fake-openai-server")
        self.url = f"http://127.0.0.1:{self._httpd.server_address[1]}/v1"

    def script(self, *replies: Reply) -> None:
        """Answer the next requests with ``replies`` (the last one repeats)."""
        if not replies:
            raise ValueError("script() needs at least one Reply")
        with self._lock:
            self._script = list(replies)

    def _next(self, body: dict[str, Any]) -> Reply:
        with self._lock:
            self.received.append(Received(body, time.monotonic()))
            return self._script[0] if len(self._script) == 1 else self._script.pop(0)

    def wait(self, seconds: float) -> bool:
        """Sleep ``seconds`` [s] unless the server is stopping; True when it is stopping."""
        return self._stop.wait(seconds)

    def __enter__(self) -> FakeOpenAIServer:
        self._thread.start()
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.close()

    def close(self) -> None:
        """Wake every sleeping or streaming handler and stop listening."""
        self._stop.set()
        if self._thread.is_alive():
            self._httpd.shutdown()
        self._httpd.server_close()


def _handler_for(server: FakeOpenAIServer) -> type[BaseHTTPRequestHandler]:
    class Handler(_FaultHandler):
        fake = server

    return Handler


class _FaultHandler(BaseHTTPRequestHandler):
    """Plays one :class:`Reply` per request."""

    fake: FakeOpenAIServer
    protocol_version = "HTTP/1.1"  # keep-alive and chunked bodies, as real endpoints use
    timeout = 30.0  # an idle keep-alive connection is dropped after this [s]

    def log_message(self, format: str, *args: Any) -> None:
        pass

    def do_POST(self) -> None:
        length = int(self.headers.get("content-length", 0))
        raw = self.rfile.read(length) if length else b"{}"
        reply = self.fake._next(json.loads(raw or b"{}"))
        try:
            self._play(reply)
        except (BrokenPipeError, ConnectionResetError):  # the client gave up: expected
            self.close_connection = True

    def _play(self, reply: Reply) -> None:
        if reply.kind == "hang" and self.fake.wait(reply.delay):
            self.close_connection = True
            return
        if reply.kind in ("ok", "hang"):
            self._send(200, json.dumps(chat_completion(reply.text)).encode(), reply.headers)
        elif reply.kind == "status":
            error = {"error": {"message": f"fake failure {reply.status}", "type": "server_error"}}
            self._send(reply.status, json.dumps(error).encode(), reply.headers)
        elif reply.kind == "cut":
            body = json.dumps(chat_completion(reply.text)).encode()
            self._send(200, body[: len(body) // 2], {"Content-Length": str(len(body))})
            self.close_connection = True
        elif reply.kind == "truncated_json":
            self._send(200, json.dumps(chat_completion(reply.text)).encode()[:40], reply.headers)
        elif reply.kind == "not_json":
            self._send(200, b"<html><body>502 Bad Gateway</body></html>",
                       {"Content-Type": "text/html"})
        elif reply.kind == "wrong_shape":
            self._send(200, json.dumps({"object": "list", "data": []}).encode(), reply.headers)
        else:
            self._endless(reply.delay)

    def _send(self, status: int, body: bytes, headers: dict[str, str]) -> None:
        merged = {"Content-Type": "application/json", "Content-Length": str(len(body)), **headers}
        self.send_response(status)
        for name, value in merged.items():
            self.send_header(name, value)
        self.end_headers()
        self.wfile.write(body)
        self.wfile.flush()

    def _endless(self, delay: float) -> None:
        """A chat completion whose content string never closes, sent chunk by chunk."""
        self.send_response(200)
        self.send_header("Content-Type", "application/json")
        self.send_header("Transfer-Encoding", "chunked")
        self.end_headers()
        self._chunk(b'{"id": "chatcmpl-fake", "object": "chat.completion", "choices": '
                    b'[{"index": 0, "message": {"role": "assistant", "content": "x = 1')
        piece = b" + 1" * 4096
        end = time.monotonic() + ENDLESS_LIMIT_S
        while time.monotonic() < end:
            self._chunk(piece)
            if self.fake.wait(delay):
                break
        self.close_connection = True

    def _chunk(self, data: bytes) -> None:
        self.wfile.write(b"%x\r\n%s\r\n" % (len(data), data))
        self.wfile.flush()
