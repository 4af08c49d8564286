"""Data sets for the store tests: a two-row CSV, random CSVs of n rows (the same n: the
same stored size), and putting one into a store as an upload would."""
from __future__ import annotations

import numpy as np

from app.datasets import formats, summary
from app.datasets.store import content_id

CSV = b"theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f\n30,0,30,180,1.5\n45,0,20,90,0.25\n"


def random_csv(n: int, seed: int) -> bytes:
    rng = np.random.default_rng(seed)
    rows = np.column_stack([rng.uniform(0, 89, n), rng.uniform(0, 360, n), rng.uniform(0, 89, n),
                            rng.uniform(0, 360, n), rng.uniform(0, 2, n)])
    return ("theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f\n"
            + "\n".join(",".join(f"{x:.6f}" for x in r) for r in rows)).encode()


def put(store, content: bytes, client: str = ""):
    """(id, delete token, data set) of ``content`` put into ``store``."""
    data = formats.load(content)
    data_id = content_id(data.format, content)
    return data_id, store.put(data_id, data, summary.summarize(data), client=client), data
