//! std test harness for deform-kernel: independent reference implementations shared by the tests.
