from pathlib import Path

import pytest

from capslide.config import load_config
from capslide.params import Parameters

ROOT = Path(__file__).resolve().parents[1]
PAPER_CONFIG = ROOT / "config" / "config.yaml"


@pytest.fixture(scope="session")
def paper_config() -> dict:
    return load_config([PAPER_CONFIG])


@pytest.fixture(scope="session")
def paper(paper_config) -> Parameters:
    return Parameters.from_config(paper_config)
