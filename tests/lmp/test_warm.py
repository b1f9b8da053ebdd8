"""Pre-warming program prefixes (what setup does) with a stand-in backend that records requests."""

import pytest

from voxposer.lmp.backends.base import LLMBackend, LLMRequest, LLMResponse
from voxposer.lmp.prompt import load_prompt
from voxposer.lmp.prompt_tags import lmp_of
from voxposer.lmp.query_forms import query_message
from voxposer.lmp.registry import LMP_SPECS, LMPConfig, get_spec
from voxposer.lmp.warm import main, warm_prefixes


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


def test_held_out_fold_is_warmed_under_its_own_prefix_ids() -> None:
    inner = PrefixRecorder()
    result = warm_prefixes(Wrapper(inner), LMPConfig(held_out_task="move_to_preposition"))
    assert result == dict.fromkeys(LMP_SPECS, "evaluated")
    ids = {r.prefix_id for r in inner.warmed}
    assert ids == {"planner~move_to_preposition", "composer~move_to_preposition",
                   "get_affordance_map~move_to_preposition"} | (
                       set(LMP_SPECS) - {"planner", "composer", "get_affordance_map"})
    for request in inner.warmed:
        spec = get_spec(lmp_of(request.prefix_id))
        fold = load_prompt(spec.name, held_out_task="move_to_preposition")
        assert request.messages[:-1] == fold.messages(query_message(spec, "x", ("table",)))[:-1]


def test_warm_cli_refuses_an_unknown_task(capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        main(["--held-out", "nope"])
    assert "invalid choice: 'nope'" in capsys.readouterr().err
