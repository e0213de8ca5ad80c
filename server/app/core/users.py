"""Named users and their API tokens (RT_USERS, RT_USERS_FILE).

RT_USERS="alice:<token>,bob:<token>" or RT_USERS_FILE=<path>, a file of lines
`<name> <token>` (blank lines and lines starting with # skipped); both may be
set, and their entries are one list. A mistake stops the server at start with
a SystemExit naming the line or entry and the problem, never the token: a
server that starts with a user missing or a short token would fail later, and
silently.

Without named users the server has one local user (its records' owner is
empty), reached without a token or with RT_API_TOKEN as before.
"""

from __future__ import annotations

import os
import re
from dataclasses import dataclass
from pathlib import Path

# A name is what owns records and shows in the viewer: plain, and never empty
# (the empty owner means "shared" or "the one local user").
NAME = re.compile(r"[A-Za-z0-9][A-Za-z0-9._-]{0,63}")
# Tokens must resist guessing: 16 characters of a random token is 96 bits and more.
MIN_TOKEN_CHARS = 16
# The name the one user of a server without named users is shown as.
LOCAL_NAME = "local"


@dataclass(frozen=True)
class User:
    name: str
    token: str

    def __repr__(self) -> str:  # settings get printed; tokens must not be
        return f"User(name={self.name!r}, token=<{len(self.token)} characters>)"


def _entries(text: str, source: str, separator: str | None) -> list[tuple[str, str, str]]:
    """(where, name, token) of each entry of an RT_USERS value (separator ':',
    entries split by commas) or a users file (separator None: whitespace, a
    line each)."""
    found = []
    if separator is None:
        pieces = [(f"{source} line {n}", line.strip()) for n, line in enumerate(text.splitlines(), 1)]
        pieces = [(where, line) for where, line in pieces if line and not line.startswith("#")]
    else:
        pieces = [(f"{source} entry {n}", part.strip()) for n, part in enumerate(text.split(","), 1) if part.strip()]
    for where, piece in pieces:
        parts = piece.split(separator, 1) if separator else piece.split(None, 1)
        name = parts[0].strip()
        token = parts[1].strip() if len(parts) == 2 else ""
        found.append((where, name, token))
    return found


def _check(entries: list[tuple[str, str, str]]) -> tuple[User, ...]:
    users: list[User] = []
    names: dict[str, str] = {}
    tokens: dict[str, str] = {}
    for where, name, token in entries:
        # Neither message shows what was written: a line holding a token alone would print it.
        if not token:
            raise SystemExit(f"{where}: expected a name and a token ('name token' in a file, "
                             "'name:token' in RT_USERS)")
        if not NAME.fullmatch(name):
            raise SystemExit(f"{where}: the user name is not 1-64 letters, digits, '.', '_' or '-' "
                             "(starting with a letter or digit)")
        if name.lower() == LOCAL_NAME:
            raise SystemExit(f"{where}: {LOCAL_NAME!r} is the name of a server's one user without named users: "
                             "choose another")
        if len(token) < MIN_TOKEN_CHARS or any(c.isspace() or not c.isprintable() for c in token):
            raise SystemExit(f"{where}: user {name!r}'s token is shorter than {MIN_TOKEN_CHARS} characters or "
                             "holds spaces or control characters (make one with `openssl rand -hex 24`)")
        if name.lower() in names:
            raise SystemExit(f"{where}: user {name!r} is named again (first at {names[name.lower()]}); "
                             "names are compared ignoring case")
        if token in tokens:
            raise SystemExit(f"{where}: user {name!r} has the same token as {tokens[token]}: "
                             "each user needs a token of their own")
        names[name.lower()] = where
        tokens[token] = f"user {name!r}"
        users.append(User(name, token))
    return tuple(users)


def load_users(environ=os.environ) -> tuple[User, ...]:
    """The named users of RT_USERS and RT_USERS_FILE; () without either.
    SystemExit naming the problem for a bad entry or an unreadable file."""
    entries = _entries(environ.get("RT_USERS", ""), "RT_USERS", ":")
    path = environ.get("RT_USERS_FILE", "")
    if path:
        try:
            text = Path(path).read_text(encoding="utf-8")
        except (OSError, UnicodeDecodeError) as e:
            raise SystemExit(f"RT_USERS_FILE={path!r}: cannot read it ({e.__class__.__name__}: "
                             f"{getattr(e, 'strerror', None) or e})") from None
        file_entries = _entries(text, f"RT_USERS_FILE {path}", None)
        if not file_entries:
            raise SystemExit(f"RT_USERS_FILE={path!r}: no users in it (lines of 'name token')")
        entries += file_entries
    users = _check(entries)
    if users and environ.get("RT_API_TOKEN"):
        raise SystemExit("RT_API_TOKEN is the token of a server without named users: with RT_USERS or "
                         "RT_USERS_FILE, give that token a name among the users instead")
    return users
