"""What `voxposer bench`'s options turn into."""

import argparse

import pytest

from voxposer.cli.bench_options import add_bench_options, bench_config


@pytest.mark.parametrize(("given", "splits"), [
    ("both", ("seen", "unseen")), ("seen,unseen", ("seen", "unseen")), ("unseen", ("unseen",)),
])
def test_splits_both_is_the_two_attribute_splits(given: str, splits: tuple[str, ...]) -> None:
    parser = argparse.ArgumentParser()
    add_bench_options(parser)
    assert bench_config(parser.parse_args(["--splits", given])).splits == splits
