"""A user's measured data from the command line: ``datasets FILE`` reads a file and
prints what ``POST /api/v1/datasets`` answers for it; ``fit FILE`` fits a model to it as
``POST /api/v1/fit`` does. The options are the API's: the fit's body fields, and the
model's parameters as every endpoint takes them (the file stands in for the data id)."""
from __future__ import annotations

import argparse
from pathlib import Path

from .options import UsageError, add_fields, add_output, check_directory, given, validate, write

DATASETS = "read a measured file (MERL .binary or CSV) and print its summary, as POST /api/v1/datasets"
FIT = "fit a model to a measured file (least squares), as POST /api/v1/fit"


def _load(path: Path, format: str | None):
    from ..datasets import formats
    from ..datasets.store import content_id
    if not path.is_file():
        raise UsageError(f"{path}: no such file")
    content = path.read_bytes()
    data = formats.load(content, format)
    return data, content_id(data.format, content)


def _format_option(parser: argparse.ArgumentParser) -> None:
    from ..datasets import formats
    parser.add_argument("--format", choices=list(formats.FORMATS), default=None,
                        help="insist on a format instead of detecting it: " + "; ".join(
                            f"{k}: {v}" for k, v in formats.FORMATS.items()).replace("%", "%%"))


def datasets(argv: list[str]) -> int:
    from ..datasets import summary
    from ..export.jsonable import json_bytes
    from ..errors import ParameterError
    parser = argparse.ArgumentParser(prog="brdf-explorer datasets", description=DATASETS + ".")
    parser.add_argument("file", type=Path)
    _format_option(parser)
    add_output(parser, required=False)
    args = parser.parse_args(argv)
    if args.output is not None:
        check_directory(args.output, args.mkdir)
    try:
        data, data_id = _load(args.file, args.format)
        answer = {"id": data_id, "format": data.format, "summary": summary.summarize(data)}
    except ParameterError as e:
        raise UsageError(f"{args.file}: {e.message}") from None
    write(json_bytes(answer), args.output)
    return 0


def fit(argv: list[str]) -> int:
    from ..errors import ParameterError
    from ..export.jsonable import json_bytes
    from ..fit.body import FitBody
    from ..fit import run as fitting
    from ..views.schemas import ModelQuery, model_values
    parser = argparse.ArgumentParser(
        prog="brdf-explorer fit", allow_abbrev=False,
        description=FIT + ". The model options are its fixed parameters and the free ones' "
                          "starting values.")
    parser.add_argument("file", type=Path)
    _format_option(parser)
    add_output(parser, required=False)
    add_fields(parser, FitBody, skip=("data", "model"))
    add_fields(parser, ModelQuery, skip=set(FitBody.model_fields))
    args = parser.parse_args(argv)
    own = {k: v for k, v in given(args, ModelQuery).items() if k not in FitBody.model_fields}
    model = model_values(validate(ModelQuery, own))
    if args.output is not None:
        check_directory(args.output, args.mkdir)
    try:
        data, data_id = _load(args.file, args.format)
        body = validate(FitBody, {**given(args, FitBody), "data": data_id, "model": model})
        run = fitting.fit_all if body.fit_all else fitting.fit
        result = run(data, body.model, body.free, body.measure, body.channel, body.seconds, body.max_points)
    except ParameterError as e:
        raise UsageError(f"--{e.param.replace('_', '-')}: {e.message}") from None
    write(json_bytes({"data": data_id, **result}), args.output)
    return 0
