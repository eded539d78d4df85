"""The exceptions of ldoem: libldoem's DriverError as Python sees it (docs/python.md)."""


class Error(Exception):
    """A libldoem error. The message is libldoem's one-line describe(); the attributes are its fields.

    kind            libldoem's ErrorKind name: timeout, connection_closed, service_failure, ...
    operation       what was attempted ("GET_STATUS", "connect", ...)
    object          on what (the endpoint text)
    errno           the system errno, 0 when none
    request_code    the service code waited for (0 outside the Scanner); request: its name
    failure_reason  service_failure: the D2 reason code (1..6), else None
    in_band_code    refused: the device's in-band code (TRANS_MEASURE 1..4, ...)
    device_status   device_fault: the status byte, else None
    code            the protocol's failure code for this kind: failure_reason, in_band_code or
                    device_status (None for the others)
    retryable       libldoem's is_retryable(); recovery: retry, reconnect, reset_device or none
    """

    kind = "system"

    def __init__(self, message, fields=None):
        super().__init__(message)
        self.message = message
        fields = dict(fields or {})
        self.kind = fields.get("kind", type(self).kind)
        self.operation = fields.get("operation", "")
        self.object = fields.get("object", "")
        self.errno = fields.get("errno", 0)
        self.request_code = fields.get("request_code", 0)
        self.request = fields.get("request")
        self.failure_reason = fields.get("failure_reason")
        self.in_band_code = fields.get("in_band_code", 0)
        self.device_status = fields.get("device_status")
        self.detail = fields.get("detail", "")
        self.retryable = fields.get("retryable", False)
        self.recovery = fields.get("recovery", "none")

    @property
    def code(self):
        if self.kind == "service_failure":
            return self.failure_reason
        if self.kind == "refused":
            return self.in_band_code
        if self.kind == "device_fault":
            return self.device_status
        return None


class Timeout(Error):
    """No reply, frame or connection before the deadline (retryable)."""
    kind = "timeout"


class ConnectionClosed(Error):
    """The peer closed or reset the connection (reconnect)."""
    kind = "connection_closed"


class ServiceFailure(Error):
    """The device answered SERVICE_FAILURE (D2); `failure_reason` says why."""
    kind = "service_failure"


class DeviceFault(Error):
    """The device's status reports a fault (motor nibble, ERROR); `device_status` is the byte."""
    kind = "device_fault"


class Refused(Error):
    """The device refused in-band; `in_band_code` is its code."""
    kind = "refused"


_BY_KIND = {cls.kind: cls for cls in (Timeout, ConnectionClosed, ServiceFailure, DeviceFault, Refused)}


def from_driver(message, fields):
    """Called by the extension module: the exception for a DriverError's fields."""
    return _BY_KIND.get(fields.get("kind"), Error)(message, fields)
