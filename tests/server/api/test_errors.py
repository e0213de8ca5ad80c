"""api/errors.py: the one mapping from the services' kinds of error to HTTP
answers, and services that never speak HTTP themselves."""

import ast
import errno
import sqlite3
from pathlib import Path

import pytest
from fastapi import FastAPI
from fastapi.testclient import TestClient

from app.api.errors import add_error_handlers, http_status
from app.services import errors
from app.services.uploads import UploadError, UploadTooLarge, UploadTypeRefused

SERVICES = Path(__file__).resolve().parents[3] / "server" / "app" / "services"


@pytest.mark.parametrize("error, status", [
    (errors.NotFound("no job with id 'x'"), 404),
    (errors.Conflict("job 'x' is running"), 409),
    (errors.Invalid("settings.width: 0 is below the minimum 1"), 422),
    (errors.Refused("bad"), 400),
    (UploadError("the file is empty"), 400),
    (UploadTooLarge("the upload is larger than the limit"), 413),
    (UploadTypeRefused("'.txt' files are not accepted"), 415),
    (errors.ServiceError("a kind without a status"), 500),
])
def test_each_kind_is_answered_with_its_status_and_its_message(error, status, tmp_path):
    app = FastAPI()
    add_error_handlers(app, tmp_path)

    @app.get("/fail")
    def fail():
        raise error

    response = TestClient(app, raise_server_exceptions=False).get("/fail")
    assert (response.status_code, response.json()) == (status, {"detail": str(error)})
    assert http_status(error) == status


@pytest.mark.parametrize("error, status", [
    (OSError(errno.ENOSPC, "No space left on device"), 507),
    (OSError(errno.EDQUOT, "Disk quota exceeded"), 507),
    (sqlite3.OperationalError("database or disk is full"), 507),
    (OSError(errno.EACCES, "Permission denied"), 500),
    (sqlite3.OperationalError("database is locked"), 500),
])
def test_a_full_disk_anywhere_is_a_507_naming_it_and_other_failures_stay_500s(error, status, tmp_path):
    app = FastAPI()
    add_error_handlers(app, tmp_path)

    @app.get("/fail")
    def fail():
        raise error

    response = TestClient(app, raise_server_exceptions=False).get("/fail")
    assert response.status_code == status
    if status == 507:
        assert "data folder is full" in response.json()["detail"]


def test_upload_refusals_are_upload_errors_of_their_kind():
    assert issubclass(UploadTooLarge, UploadError) and issubclass(UploadTooLarge, errors.TooLarge)
    assert issubclass(UploadTypeRefused, UploadError) and issubclass(UploadTypeRefused, errors.UnsupportedType)


@pytest.mark.parametrize("module", sorted(p.name for p in SERVICES.glob("*.py")))
def test_services_do_not_import_the_web_framework(module):
    tree = ast.parse((SERVICES / module).read_text())
    imported = [node.module or "" for node in tree.body if isinstance(node, ast.ImportFrom)]
    imported += [alias.name for node in tree.body if isinstance(node, ast.Import) for alias in node.names]
    assert not [name for name in imported if name.split(".")[0] in ("fastapi", "starlette") or name.startswith("..api")]
