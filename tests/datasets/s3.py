"""An S3-compatible server for the tests, on this machine: moto's standalone server
(``moto[server]``, in the test extra) on a free 127.0.0.1 port, one per test process.
The process's AWS settings point at it (dummy credentials, ``AWS_ENDPOINT_URL``, no
instance-metadata lookup), so s3fs, boto3 and the application's store reach nothing
else. ``s3_url`` is a fresh bucket's URL for each test."""
from __future__ import annotations

import logging
import uuid

import boto3
import pytest
from moto.server import ThreadedMotoServer

#: the AWS settings of the test process: dummy credentials, and no file or metadata
#: service that could name real ones
AWS_ENV = {"AWS_ACCESS_KEY_ID": "testing", "AWS_SECRET_ACCESS_KEY": "testing",
           "AWS_SESSION_TOKEN": "testing", "AWS_DEFAULT_REGION": "us-east-1",
           "AWS_EC2_METADATA_DISABLED": "true", "AWS_CONFIG_FILE": "/dev/null",
           "AWS_SHARED_CREDENTIALS_FILE": "/dev/null"}


@pytest.fixture(scope="session")
def s3_endpoint():
    """The server's URL, with the process's AWS settings pointing at it."""
    logging.getLogger("werkzeug").setLevel(logging.WARNING)       # no line per request
    server = ThreadedMotoServer(ip_address="127.0.0.1", port=0, verbose=False)
    server.start()
    host, port = server.get_host_and_port()
    endpoint = f"http://{host}:{port}"
    with pytest.MonkeyPatch.context() as mp:
        for name, value in {**AWS_ENV, "AWS_ENDPOINT_URL": endpoint}.items():
            mp.setenv(name, value)
        yield endpoint
    server.stop()


@pytest.fixture(scope="session")
def s3_client(s3_endpoint):
    """boto3's client of the server, to look at or change objects behind the store."""
    return boto3.client("s3")


@pytest.fixture
def s3_bucket(s3_client):
    """A new, empty bucket's name."""
    name = f"brdf-{uuid.uuid4().hex[:16]}"
    s3_client.create_bucket(Bucket=name)
    return name


@pytest.fixture
def s3_url(s3_bucket):
    """A prefix in a new bucket, as BRDF_DATA_URL would name it."""
    return f"s3://{s3_bucket}/datasets"
