"""Pre-warming program prefixes (what setup does) with a stand-in backend that records requests."""

from voxposer.lmp.backends.base import LLMBackend, LLMRequest, LLMResponse
from voxposer.lmp.prompt import load_prompt
from voxposer.lmp.registry import LMP_SPECS, get_spec
from voxposer.lmp.runtime import query_message
from voxposer.lmp.warm import warm_prefixes


class PrefixRecorder(LLMBackend):
    """Records warm_prefix requests (a test double)."""

    name = "recorder"

    def __init__(self) -> None:
        self.warmed: list[LLMRequest] = []

    @property
    def model(self) -> str:
        return "recorder"

    def complete(self, request: LLMRequest) -> LLMResponse:
        raise AssertionError("warming must not generate")

    def warm_prefix(self, request: LLMRequest) -> dict[str, object]:
        self.warmed.append(request)
        return {"prefix": "evaluated"}


class Wrapper(LLMBackend):
    name = "wrapper"

    def __init__(self, inner: LLMBackend) -> None:
        self.inner = inner

    @property
    def model(self) -> str:
        return self.inner.model

    def complete(self, request: LLMRequest) -> LLMResponse:
        return self.inner.complete(request)


def test_every_program_prefix_is_warmed_as_the_runtime_will_send_it() -> None:
    inner = PrefixRecorder()
    result = warm_prefixes(Wrapper(inner))  # reaches through cache/override wrappers
    assert result == dict.fromkeys(LMP_SPECS, "evaluated")
    for request in inner.warmed:
        spec = get_spec(request.prefix_id)
        runtime_messages = load_prompt(spec.name).messages(query_message(spec, "x", ("table",)))
        assert request.messages[:-1] == runtime_messages[:-1]  # identical prefix


def test_backends_without_prefix_states_have_nothing_to_warm() -> None:
    class Endpoint(LLMBackend):
        name = "endpoint"
        model = "m"  # type: ignore[assignment]

        def complete(self, request: LLMRequest) -> LLMResponse:
            raise AssertionError

    assert set(warm_prefixes(Endpoint()).values()) == {"unsupported"}
