"""services/data_access.py: where workers reach the server, and which workers
see its data folder (the id the server wrote there, and room to write)."""

import socket

from app.services import data_access
from app.services.data_access import DataAccess, server_access, sees_data_folder, worker_url
from service import service_settings


def test_workers_reach_the_url_set_else_the_bound_address_else_this_machine(tmp_path):
    assert worker_url(service_settings(tmp_path, server_url="http://render-api:8000/")) == "http://render-api:8000"
    assert worker_url(service_settings(tmp_path, host="10.0.0.5", port=9000)) == "http://10.0.0.5:9000"
    assert worker_url(service_settings(tmp_path, host="::1", port=9000)) == "http://[::1]:9000"
    assert worker_url(service_settings(tmp_path, host="0.0.0.0", port=8000)) == f"http://{socket.gethostname()}:8000"


def test_the_folder_id_is_kept_across_starts_and_the_secret_is_not(tmp_path):
    settings = service_settings(tmp_path)
    first, second = server_access(settings), server_access(settings)
    assert first.folder_id == second.folder_id == (tmp_path / data_access.FOLDER_ID_FILE).read_text()
    assert first.secret != second.secret and len(first.secret) >= 32


def test_a_worker_sees_the_folder_only_with_the_servers_id_in_it(tmp_path, monkeypatch):
    monkeypatch.setattr(data_access, "_sees", {})
    access = server_access(service_settings(tmp_path))
    assert sees_data_folder(access)
    other = tmp_path / "a-volume-of-its-own"
    (other / "jobs").mkdir(parents=True)
    (other / data_access.FOLDER_ID_FILE).write_text("another-servers-id")
    assert not sees_data_folder(DataAccess(str(other), access.folder_id, "", ""))
    assert not sees_data_folder(DataAccess(str(tmp_path / "missing"), access.folder_id, "", ""))
