"""Fixtures: the installed default model, a real llama.cpp OpenAI-compatible server, and a stub
HTTP server that misbehaves on purpose. Everything listens on 127.0.0.1 only."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request
from collections.abc import Iterator
from dataclasses import dataclass, field
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import pytest

from voxposer.lmp.backends.config import available_cores, configure_openmp, default_model_dir
from voxposer.lmp.backends.default_model import DEFAULT_MODEL, installed_path

configure_openmp()  # before anything imports llama_cpp (libgomp reads it once, when loaded)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


@pytest.fixture(scope="session")
def default_model_path() -> Path:
    """The verified default GGUF (skips only when `bash scripts/setup.sh` has not installed it)."""
    path = installed_path(default_model_dir())
    if path is None:
        pytest.skip(f"default model {DEFAULT_MODEL.name} not installed (bash scripts/setup.sh)")
    pytest.importorskip("llama_cpp")
    return path


@pytest.fixture(scope="session")
def llama_server(
    default_model_path: Path, tmp_path_factory: pytest.TempPathFactory
) -> Iterator[str]:
    """llama-cpp-python's OpenAI-compatible server on a free port; yields its base URL."""
    pytest.importorskip("llama_cpp.server")
    log_path = tmp_path_factory.mktemp("llama_server") / "server.log"
    port = free_port()
    cmd = [
        sys.executable, "-m", "llama_cpp.server",
        "--model", str(default_model_path),
        "--model_alias", "default",
        "--host", "127.0.0.1", "--port", str(port),
        "--n_ctx", "2048", "--n_threads", str(available_cores()),
    ]  # fmt: skip
    log_file = open(log_path, "w")  # a file, not a pipe: a full pipe would block the server
    env = dict(os.environ)
    configure_openmp(env)
    proc = subprocess.Popen(cmd, stdout=log_file, stderr=subprocess.STDOUT, env=env)
    base = f"http://127.0.0.1:{port}/v1"
    deadline = time.monotonic() + 180
    try:
        while True:
            if proc.poll() is not None:
                tail = log_path.read_text(errors="replace")[-2000:]
                pytest.fail(f"llama_cpp.server exited with {proc.returncode}: {tail}")
            try:
                with urllib.request.urlopen(f"{base}/models", timeout=2) as r:
                    if r.status == 200:
                        break
            except (urllib.error.URLError, ConnectionError, TimeoutError):
                pass
            if time.monotonic() > deadline:
                pytest.fail("llama_cpp.server did not start within 180 s")
            time.sleep(0.5)
        yield base
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=20)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()
        log_file.close()


@dataclass
class StubServer:
    """A local HTTP server whose answers a test scripts: a list of (status, body, headers,
    delay [s]) consumed one per request; the last one repeats."""

    url: str
    script: list[tuple[int, dict, dict, float]] = field(default_factory=list)
    requests: list[dict] = field(default_factory=list)
    headers: list[dict[str, str]] = field(default_factory=list)


def chat_body(text: str = "x = 1") -> dict:
    """A minimal valid OpenAI chat completion."""
    return {
        "id": "chatcmpl-1",
        "object": "chat.completion",
        "created": int(time.time()),
        "model": "stub-model",
        "choices": [
            {
                "index": 0,
                "message": {"role": "assistant", "content": text},
                "finish_reason": "stop",
            }
        ],
        "usage": {"prompt_tokens": 5, "completion_tokens": 3, "total_tokens": 8},
    }


@pytest.fixture
def stub_server() -> Iterator[StubServer]:
    stub = StubServer(url="")
    stop = threading.Event()

    class Handler(BaseHTTPRequestHandler):
        def log_message(self, *args: object) -> None:
            pass

        def do_POST(self) -> None:
            length = int(self.headers.get("content-length", 0))
            stub.headers.append({k.lower(): v for k, v in self.headers.items()})
            stub.requests.append(json.loads(self.rfile.read(length) or b"{}"))
            index = min(len(stub.requests), len(stub.script)) - 1
            status, body, headers, delay = stub.script[index]
            if delay:
                stop.wait(delay)
            try:
                payload = json.dumps(body).encode()
                self.send_response(status)
                self.send_header("content-type", "application/json")
                self.send_header("content-length", str(len(payload)))
                for k, v in headers.items():
                    self.send_header(k, v)
                self.end_headers()
                self.wfile.write(payload)
            except (BrokenPipeError, ConnectionResetError):
                pass

    server = ThreadingHTTPServer(("127.0.0.1", 0), Handler)
    server.daemon_threads = True
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    stub.url = f"http://127.0.0.1:{server.server_address[1]}/v1"
    try:
        yield stub
    finally:
        stop.set()
        server.shutdown()
        server.server_close()


@pytest.fixture
def clean_env(monkeypatch: pytest.MonkeyPatch) -> None:
    """No VOXPOSER_* / OPENAI_* variables leak into a test."""
    for var in list(os.environ):
        if var.startswith(("VOXPOSER_", "OPENAI_")):
            monkeypatch.delenv(var, raising=False)
