"""Reading a chat completion out of an endpoint's raw response body, trusting nothing.

The ``openai`` SDK parses leniently: a body that is not JSON comes back as a ``str``, a JSON
document without the expected fields becomes a model whose attributes are missing, and a
truncated document raises a bare ``json.JSONDecodeError``. :func:`parse_chat_body` checks the few
fields voxposer uses and raises :class:`ChatBodyError` saying what was wrong and whether asking
again may help (a body garbled or cut short on the way) or not (a server speaking another
protocol, or one that ignores the generation limit).
"""

from __future__ import annotations

import json
from typing import Any, NamedTuple

#: an answer longer than max_tokens × this many characters cannot respect max_tokens (code
#: averages 3–4 characters per token; even runs of whitespace stay far below this)
MAX_CHARS_PER_TOKEN = 32


class ChatAnswer(NamedTuple):
    """What voxposer keeps of a chat completion.

    Attributes:
        text: the first choice's message content ("" when the server sent none).
        finish_reason: why generation stopped ("stop", "length", …), None when not said.
        prompt_tokens: tokens in the prompt (0 when not reported).
        completion_tokens: tokens generated (0 when not reported).
    """

    text: str
    finish_reason: str | None
    prompt_tokens: int
    completion_tokens: int


class ChatBodyError(Exception):
    """A 200 response whose body is not a usable chat completion.

    Attributes:
        retryable: True when the body looks damaged in transit (asking again may help).
    """

    def __init__(self, message: str, retryable: bool) -> None:
        self.retryable = retryable
        super().__init__(message)


def parse_chat_body(body: bytes, content_type: str, max_tokens: int) -> ChatAnswer:
    """The answer in ``body``, a chat completion requested with ``max_tokens`` [tokens].

    Raises:
        ChatBodyError: the body is not JSON (retryable), is JSON of another shape, carries an
            ``error`` object, or holds more text than ``max_tokens`` tokens can (not retryable).
    """
    try:
        data = json.loads(body)
    except (UnicodeDecodeError, json.JSONDecodeError) as exc:
        what = ("truncated or invalid JSON" if "json" in content_type.lower()
                else f"{content_type or 'untyped'} content, not JSON")
        raise ChatBodyError(f"a {len(body)}-byte body of {what} ({exc}): {_snippet(body)}",
                            retryable=True) from exc
    if not isinstance(data, dict):
        raise ChatBodyError(f"a JSON {type(data).__name__}, not a chat completion object: "
                            f"{_snippet(body)}", retryable=False)
    if data.get("error") and not data.get("choices"):
        raise ChatBodyError(f"an error instead of a completion: {_error_text(data['error'])}",
                            retryable=False)
    choices = data.get("choices")
    if not isinstance(choices, list) or not choices:
        raise ChatBodyError(f"no choices (fields: {', '.join(sorted(data)) or 'none'})",
                            retryable=False)
    first = choices[0]
    message = first.get("message") if isinstance(first, dict) else None
    content = message.get("content") if isinstance(message, dict) else None
    if not isinstance(message, dict) or not isinstance(content, (str, type(None))):
        raise ChatBodyError(f"choices[0] not a chat message with text content: "
                            f"{_snippet(json.dumps(first).encode())}", retryable=False)
    text = content or ""
    limit = max_tokens * MAX_CHARS_PER_TOKEN
    if len(text) > limit:
        raise ChatBodyError(
            f"an answer of {len(text)} characters, more than max_tokens={max_tokens} allows "
            f"({limit} at {MAX_CHARS_PER_TOKEN} per token): the endpoint ignores max_tokens",
            retryable=False)
    usage = data.get("usage")
    usage = usage if isinstance(usage, dict) else {}
    reason = first.get("finish_reason")
    return ChatAnswer(text=text, finish_reason=reason if isinstance(reason, str) else None,
                      prompt_tokens=_count(usage, "prompt_tokens"),
                      completion_tokens=_count(usage, "completion_tokens"))


def _count(usage: dict[str, Any], name: str) -> int:
    value = usage.get(name)
    return value if isinstance(value, int) and value >= 0 else 0


def _error_text(error: object) -> str:
    if isinstance(error, dict):
        return str(error.get("message") or error)[:300]
    return str(error)[:300]


def _snippet(body: bytes, limit: int = 120) -> str:
    text = " ".join(body[: limit * 4].decode("utf-8", "replace").split())
    return repr(text if len(text) <= limit else text[: limit - 1] + "…")
