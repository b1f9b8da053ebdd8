"""Loading the vision models' weights: from a local directory, or a model id already in the
local Hugging Face cache; nothing is ever downloaded.

torch and transformers (the ``vision`` extra) are imported here, lazily, so importing
:mod:`voxposer` or running ``voxposer run`` never imports them.
"""

from __future__ import annotations

import importlib
import json
import logging
from pathlib import Path
from types import ModuleType
from typing import Any, Final

from voxposer.errors import ConfigError

log = logging.getLogger(__name__)

#: model class name → the ``model_type`` its ``config.json`` must declare.
MODEL_TYPES: Final = {"Owlv2ForObjectDetection": "owlv2", "SamModel": "sam"}


def require(module: str) -> ModuleType:
    """Import ``module`` ("torch", "transformers"), or explain how to install it.

    Raises:
        ConfigError: the module is not installed (names the ``vision`` extra).
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise ConfigError(f"open-vocabulary perception needs {module!r}, which is not "
                          f"installed; install the vision extra: pip install "
                          f"'voxposer[vision]' ({exc})") from exc


def _model_type(source: str, model_class: str) -> str:
    """The ``model_type`` of the weights at ``source`` (a directory or a cached model id)."""
    expected = MODEL_TYPES[model_class]
    path = Path(source).expanduser()
    if path.is_dir():
        config = path / "config.json"
        if not config.is_file():
            raise ConfigError(f"{path} holds no config.json; expected the weights of a "
                              f"{model_class} (model_type {expected!r}) saved with "
                              "save_pretrained")
        try:
            return str(json.loads(config.read_text()).get("model_type", ""))
        except (OSError, ValueError) as exc:
            raise ConfigError(f"{config} is not a readable model config ({exc}); expected a "
                              f"{model_class}") from exc
    if path.exists() or source.startswith((".", "/", "~")) or source.count("/") != 1:
        raise ConfigError(f"no model directory at {source!r}; expected a directory holding a "
                          f"{model_class} (model_type {expected!r}) saved with save_pretrained")
    transformers = require("transformers")
    try:
        config = transformers.AutoConfig.from_pretrained(source, local_files_only=True)
    except (OSError, ValueError) as exc:
        raise ConfigError(f"{source!r} is neither a model directory nor a model id in the local "
                          f"Hugging Face cache (nothing is downloaded); expected a {model_class} "
                          f"(model_type {expected!r})") from exc
    return str(config.model_type)


def load_model(source: str | Path, model_class: str) -> Any:
    """The ``transformers`` model ``model_class`` ("Owlv2ForObjectDetection", "SamModel") with
    the weights at ``source``, in eval mode on the CPU.

    Args:
        source: a directory written by ``save_pretrained``, or a model id already in the local
            Hugging Face cache (passed to ``from_pretrained`` with ``local_files_only=True``).
        model_class: the class to load.

    Raises:
        ConfigError: the path does not exist, holds no model or another model type (names the
            path and the expected class), or the vision extra is missing.
    """
    source = str(source)
    found = _model_type(source, model_class)
    expected = MODEL_TYPES[model_class]
    if found != expected:
        raise ConfigError(f"{source!r} holds a {found or 'untyped'!r} model; expected a "
                          f"{model_class} (model_type {expected!r})")
    cls = getattr(require("transformers"), model_class)
    try:
        model = cls.from_pretrained(source, local_files_only=True)
    except (OSError, ValueError, RuntimeError) as exc:
        raise ConfigError(f"could not load a {model_class} from {source!r}: {exc}") from exc
    log.debug("loaded %s from %s", model_class, source)
    return model.eval()


def load_tokenizer(source: str | Path) -> Any:
    """The tokenizer saved beside the model at ``source`` (local files only).

    Raises:
        ConfigError: no tokenizer is saved there.
    """
    transformers = require("transformers")
    try:
        return transformers.AutoTokenizer.from_pretrained(str(source), local_files_only=True)
    except (OSError, ValueError, TypeError) as exc:
        raise ConfigError(f"no tokenizer could be loaded from {str(source)!r} ({exc}); save the "
                          "detector's tokenizer beside its weights") from exc


def image_stats(source: str | Path, default_mean: tuple[float, float, float],
                default_std: tuple[float, float, float]
                ) -> tuple[tuple[float, ...], tuple[float, ...]]:
    """Per-channel normalisation (mean, std) of images in [0, 1], from the
    ``preprocessor_config.json`` saved at ``source`` when there is one, else the defaults."""
    config = Path(str(source)).expanduser() / "preprocessor_config.json"
    if not config.is_file():
        return default_mean, default_std
    data = json.loads(config.read_text())
    return (tuple(float(v) for v in data.get("image_mean", default_mean)),
            tuple(float(v) for v in data.get("image_std", default_std)))
