"""What every command shares: options spelled like the API's query parameters (from the
same pydantic models the API validates with), the output file and its directory, and the
one error a command line can have (exit status 2)."""
from __future__ import annotations

import argparse
import sys
import typing
from pathlib import Path

from pydantic import BaseModel, ValidationError


class UsageError(Exception):
    """A bad command line: printed as ``brdf-explorer CMD: message``, exit status 2."""


def option(name: str) -> str:
    """The command-line spelling of a query parameter: ``theta_i_deg`` → ``--theta-i-deg``."""
    return "--" + name.replace("_", "-")


def add_fields(parser: argparse.ArgumentParser, model: type[BaseModel], skip=()) -> None:
    """One option per field of ``model``, with its description and default; booleans get
    ``--x/--no-x``. Values stay strings: the model validates them as the API does."""
    for name, field in model.model_fields.items():
        if name in skip:
            continue
        help_text = (field.description or "").replace("%", "%%")
        default = field.default
        if field.annotation is bool:
            parser.add_argument(option(name), dest=name, action=argparse.BooleanOptionalAction,
                                default=None, help=f"{help_text} (default {default})")
        else:
            shown = "" if default is None or field.is_required() else f" (default {default})"
            parser.add_argument(option(name), dest=name, default=None, metavar="VALUE",
                                help=help_text + shown)


def given(args: argparse.Namespace, model: type[BaseModel]) -> dict:
    """The options the user gave that belong to ``model`` (unset ones keep its defaults);
    a list field takes comma-separated values (``--free alpha,f0``)."""
    out = {}
    for k, v in vars(args).items():
        if k in model.model_fields and v is not None:
            is_list = typing.get_origin(model.model_fields[k].annotation) is list
            out[k] = v.split(",") if is_list and isinstance(v, str) else v
    return out


def validate(model: type[BaseModel], values: dict) -> BaseModel:
    """``values`` as ``model``, its errors as one UsageError naming each option."""
    try:
        return model.model_validate(values)
    except ValidationError as e:
        lines = [f"{option(str(err['loc'][0])) if err['loc'] else 'options'}: {err['msg']}"
                 for err in e.errors()]
        raise UsageError("\n".join(lines)) from None


def add_output(parser: argparse.ArgumentParser, required: bool) -> None:
    """``-o FILE`` (stdout when optional and absent) and ``--mkdir``."""
    parser.add_argument("-o", "--output", required=required, type=Path,
                        help="file to write" + ("" if required else " (default: standard output)"))
    add_mkdir(parser)


def add_mkdir(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--mkdir", action="store_true",
                        help="create the output's directory if it does not exist")


def check_directory(path: Path, mkdir: bool) -> None:
    """A missing directory is an error naming it, unless ``--mkdir`` asks to create it:
    a typo in a path should not scatter files into new directories."""
    directory = path.parent
    if directory.exists():
        if not directory.is_dir():
            raise UsageError(f"{directory} is not a directory")
        return
    if not mkdir:
        raise UsageError(f"directory {directory} does not exist (create it, or add --mkdir)")
    directory.mkdir(parents=True, exist_ok=True)


def write(body: bytes, output: Path | None) -> None:
    """``body`` into ``output``, or onto standard output (a newline added after text)."""
    if output is None:
        sys.stdout.buffer.write(body if body.endswith(b"\n") else body + b"\n")
        sys.stdout.flush()
    else:
        output.write_bytes(body)
