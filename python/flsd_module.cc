// The Python module `flsd`: flsd::Client's typed calls for scripts. Refused calls raise
// flsd.CallError (its .reply says why); state, skills and task reports are read-only objects
// whose vectors are NumPy arrays when NumPy is installed and tuples when not. Network waits
// release the GIL; Task.wait() wakes every 50 ms for Ctrl-C, which stops the robot.

#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "client/client.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace flsd {
namespace {

using Millis = std::chrono::milliseconds;

Millis ToMillis(double seconds, const char* name) {
  if (!std::isfinite(seconds) || seconds < 0.0) {
    throw py::value_error(std::string(name) + " must be a finite number of seconds >= 0, got " + std::to_string(seconds));
  }
  return Millis(static_cast<int64_t>(seconds * 1000.0));
}

// numpy, or None when it is not installed; looked up once, at import.
py::object& NumPy() {
  static py::object* numpy = new py::object(py::none());  // never destroyed: it outlives the interpreter
  return *numpy;
}

template <typename T, std::size_t N>
py::object Vector(const std::array<T, N>& values) {
  py::tuple t(N);
  for (std::size_t i = 0; i < N; ++i) t[i] = values[i];
  return NumPy().is_none() ? py::object(t) : NumPy().attr("array")(t);
}

// A planned path, x0 y0 x1 y1 ...: an (N, 2) array, or a tuple of (x, y).
py::object Path(const std::vector<double>& xy) {
  py::tuple points(xy.size() / 2);
  for (std::size_t i = 0; i + 1 < xy.size(); i += 2) points[i / 2] = py::make_tuple(xy[i], xy[i + 1]);
  return NumPy().is_none() ? py::object(points) : NumPy().attr("array")(points, "dtype"_a = "float64").attr("reshape")(-1, 2);
}

// A read-only record class: each field a property, listed in order by __repr__ and as_dict().
template <typename T>
class Record {
 public:
  Record(py::module_& m, const char* name, const char* doc) : cls_(m, name, doc), fields_(std::make_shared<std::vector<std::string>>()) {}

  template <typename Get>
  Record& Field(const char* name, Get get) {
    cls_.def_property_readonly(name, get);
    fields_->push_back(name);
    return *this;
  }

  py::class_<T>& Done() {
    auto fields = fields_;
    cls_.def("as_dict", [fields](py::object self) {
      py::dict d;
      for (const std::string& f : *fields) d[f.c_str()] = self.attr(f.c_str());
      return d;
    }, "The fields as a dict.");
    cls_.def("__repr__", [fields](py::object self) {
      std::string text = py::str(self.attr("__class__").attr("__name__"));
      text += "(";
      for (std::size_t i = 0; i < fields->size(); ++i) {
        text += (i ? ", " : "") + (*fields)[i] + "=" + std::string(py::repr(self.attr((*fields)[i].c_str())));
      }
      return text + ")";
    });
    return cls_;
  }

 private:
  py::class_<T> cls_;
  std::shared_ptr<std::vector<std::string>> fields_;
};

// A long call and the client it came from, which the Python object keeps alive.
struct PyTask {
  Task task;
  Client* client;
};

py::handle CallErrorType() {
  static py::handle type = [] {
    py::object base = py::module_::import("builtins").attr("RuntimeError");
    return py::handle(PyErr_NewExceptionWithDoc("flsd.CallError", "skilld refused a call, or did not answer; .reply says why",
                                                base.ptr(), nullptr));
  }();
  return type;
}

Reply Checked(Reply r) {
  if (!r.ok()) throw CallError(std::move(r));
  return r;
}

PyTask Started(Task task, Client& client) {
  if (!task.accepted()) throw CallError(task.reply());
  return PyTask{std::move(task), &client};
}

// Waits for the task; Ctrl-C stops the robot and raises KeyboardInterrupt.
bool WaitForTask(const PyTask& t, std::optional<double> timeout) {
  const auto start = std::chrono::steady_clock::now();
  const std::optional<Millis> limit = timeout ? std::optional<Millis>(ToMillis(*timeout, "timeout")) : std::nullopt;
  for (;;) {
    Millis slice{50};
    if (limit) slice = std::min(slice, std::max(Millis(0), *limit - std::chrono::duration_cast<Millis>(std::chrono::steady_clock::now() - start)));
    bool done;
    {
      py::gil_scoped_release nogil;
      done = t.task.Wait(slice);
    }
    if (done) return true;
    if (PyErr_CheckSignals() != 0) {
      {
        py::gil_scoped_release nogil;
        (void)t.client->Stop();
      }
      throw py::error_already_set();
    }
    if (limit && std::chrono::steady_clock::now() - start >= *limit) return false;
  }
}

std::unique_ptr<Client> Connect(int domain, const std::string& partition, const std::string& client_id, double wait,
                                std::string security) {
  if (domain < 0 || domain > 232) throw py::value_error("domain must be in [0, 232] (DDS), got " + std::to_string(domain));
  Client::Options options;
  options.domain_id = domain;
  options.partition = partition;
  options.client_id = client_id;
  // As skillctl --security: an identity's security.yaml from scripts/make_pki.sh, or $FLSD_SECURITY.
  if (security.empty() && std::getenv("FLSD_SECURITY")) security = std::getenv("FLSD_SECURITY");
  if (!security.empty()) {
    try {
      options.security = dds::LoadSecurityFile(security);
    } catch (const std::exception& e) {
      throw py::value_error("security: " + std::string(e.what()));
    }
  }
  const Millis timeout = ToMillis(wait, "wait");
  auto client = std::make_unique<Client>(options);
  bool found;
  {
    py::gil_scoped_release nogil;
    found = client->WaitForServer(timeout);
  }
  if (!found) {
    char text[200];
    std::snprintf(text, sizeof text, "no skilld answers on DDS domain %d, partition '%s' (waited %.1f s)", domain,
                  partition.c_str(), wait);
    PyErr_SetString(PyExc_TimeoutError, text);
    throw py::error_already_set();
  }
  return client;
}

}  // namespace
}  // namespace flsd

using namespace flsd;

PYBIND11_MODULE(flsd, m) {
  m.doc() = "Client of skilld, the FLSD skill server for the Unitree A1 (docs/clients.md)";
  try {
    NumPy() = py::module_::import("numpy");
  } catch (const py::error_already_set&) {
    PyErr_Clear();  // no NumPy: vectors are tuples
  }

  m.attr("CallError") = CallErrorType();
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const CallError& e) {
      py::object error = py::reinterpret_borrow<py::object>(CallErrorType())(e.what());
      error.attr("reply") = py::cast(e.reply());
      PyErr_SetObject(CallErrorType().ptr(), error.ptr());
    }
  });

  // Enums print as on the wire ("not in control", "lease lost").
  py::enum_<ReplyStatus> reply_status(m, "ReplyStatus");
  for (const EnumName<ReplyStatus>& n : kReplyStatusNames) reply_status.value(n.identifier, n.value);
  py::enum_<Mode> mode(m, "Mode");
  for (const EnumName<Mode>& n : kModeNames) mode.value(n.identifier, n.value);
  py::enum_<TaskState> task_state(m, "TaskState");
  for (const EnumName<TaskState>& n : kTaskStateNames) task_state.value(n.identifier, n.value);

  // Replaces pybind11's "Mode.STAND" (def would add an overload behind it).
  reply_status.attr("__str__") = py::cpp_function([](ReplyStatus v) { return Name(v); }, py::is_method(reply_status));
  mode.attr("__str__") = py::cpp_function([](Mode v) { return Name(v); }, py::is_method(mode));
  task_state.attr("__str__") = py::cpp_function([](TaskState v) { return Name(v); }, py::is_method(task_state));

  Record<Reply>(m, "Reply", "A reply: status, message, and the safety trips since this client's last reply")
      .Field("status", [](const Reply& r) { return r.status; })
      .Field("message", [](const Reply& r) { return r.message; })
      .Field("safety_report", [](const Reply& r) { return r.safety_report; })
      .Field("request_id", [](const Reply& r) { return r.request_id; })
      .Done()
      .def_property_readonly("ok", &Reply::ok)
      .def("__str__", &Reply::Describe);

  Record<SkillInfo>(m, "SkillInfo", "What the library measured of one skill")
      .Field("id", [](const SkillInfo& s) { return s.id; })
      .Field("linear_velocity", [](const SkillInfo& s) { return Vector(s.linear_velocity); })
      .Field("angular_velocity", [](const SkillInfo& s) { return Vector(s.angular_velocity); })
      .Field("base_height", [](const SkillInfo& s) { return s.base_height; })
      .Field("gait_frequency", [](const SkillInfo& s) { return s.gait_frequency; })
      .Field("survival_steps", [](const SkillInfo& s) { return s.survival_steps; })
      .Done();

  Record<TaskReport>(m, "TaskReport", "The progress, then the result, of a long call")
      .Field("call", [](const TaskReport& t) { return t.call; })
      .Field("state", [](const TaskReport& t) { return t.state; })
      .Field("elapsed", [](const TaskReport& t) { return t.elapsed; })
      .Field("remaining", [](const TaskReport& t) { return t.remaining; })
      .Field("message", [](const TaskReport& t) { return t.message; })
      .Field("path", [](const TaskReport& t) { return Path(t.path); })
      .Field("client_id", [](const TaskReport& t) { return t.client_id; })
      .Field("request_id", [](const TaskReport& t) { return t.request_id; })
      .Done()
      .def_property_readonly("ended", &TaskReport::ended);

  Record<StateReport>(m, "StateReport", "One sample of skilld's state topic")
      .Field("time", [](const StateReport& s) { return s.time; })
      .Field("tick", [](const StateReport& s) { return s.tick; })
      .Field("backend", [](const StateReport& s) { return s.backend; })
      .Field("mode", [](const StateReport& s) { return s.mode; })
      .Field("skill", [](const StateReport& s) { return s.skill; })
      .Field("position", [](const StateReport& s) { return Vector(s.position); })
      .Field("orientation", [](const StateReport& s) { return Vector(s.orientation); })
      .Field("yaw", [](const StateReport& s) { return s.yaw(); })
      .Field("linear_velocity", [](const StateReport& s) { return Vector(s.linear_velocity); })
      .Field("angular_velocity", [](const StateReport& s) { return Vector(s.angular_velocity); })
      .Field("joint_position", [](const StateReport& s) { return Vector(s.joint_position); })
      .Field("joint_velocity", [](const StateReport& s) { return Vector(s.joint_velocity); })
      .Field("joint_torque", [](const StateReport& s) { return Vector(s.joint_torque); })
      .Field("foot_contact", [](const StateReport& s) { return Vector(s.foot_contact); })
      .Field("faults", [](const StateReport& s) { return s.faults; })
      .Field("fault_message", [](const StateReport& s) { return s.fault_message; })
      .Field("controller", [](const StateReport& s) { return s.controller; })
      .Field("deadline_misses", [](const StateReport& s) { return s.deadline_misses; })
      .Field("requests_dropped", [](const StateReport& s) { return s.requests_dropped; })
      .Field("task", [](const StateReport& s) { return s.task; })
      .Done();

  py::class_<PyTask>(m, "Task", "A long call the server accepted; its client stays alive with it")
      .def_property_readonly("reply", [](const PyTask& t) { return t.task.reply(); })
      .def_property_readonly("request_id", [](const PyTask& t) { return t.task.request_id(); })
      .def("progress", [](const PyTask& t) { return t.task.Progress(); }, "The latest report (state NONE until the state topic has it)")
      .def("done", [](const PyTask& t) { return t.task.Done(); })
      .def_property_readonly("succeeded", [](const PyTask& t) { return t.task.Succeeded(); })
      .def("wait", &WaitForTask, "timeout"_a = py::none(),
           "Blocks until the task ends (True) or `timeout` seconds pass (False). Ctrl-C stops the robot.")
      .def("__repr__", [](const PyTask& t) {
        const TaskReport p = t.task.Progress();
        return "Task(" + std::to_string(t.task.request_id()) + ", " + Name(p.state) + ")";
      });

  py::class_<Client>(m, "Client",
                     "A connection to skilld. `with flsd.Client() as robot:` takes control for the block and "
                     "releases it after; leaving it by an exception (Ctrl-C too) stops the robot first.")
      .def(py::init(&Connect), "domain"_a = 0, "partition"_a = "flsd", "client_id"_a = "", "wait"_a = 5.0,
           "security"_a = "",
           "Connects and waits up to `wait` s for a server (TimeoutError if none answers). `security`: DDS "
           "Security, an identity's security.yaml from scripts/make_pki.sh (default: $FLSD_SECURITY); the "
           "client's id is then its authenticated identity. One identity per Python process (Cyclone's rule).")
      .def_property_readonly("id", &Client::id)
      .def_property_readonly("lost_control", &Client::lost_control)
      .def("list_skills", [](Client& c) {
        py::gil_scoped_release nogil;
        return c.ListSkills();
      })
      .def("status", [](Client& c) {
        py::gil_scoped_release nogil;
        return Checked(c.Status());
      })
      .def("acquire_control", [](Client& c) {
        py::gil_scoped_release nogil;
        return Checked(c.AcquireControl());
      })
      .def("release_control", [](Client& c) {
        py::gil_scoped_release nogil;
        return Checked(c.ReleaseControl());
      })
      .def("execute_skill", [](Client& c, int skill, double duration) {
        py::gil_scoped_release nogil;
        return Started(c.ExecuteSkill(skill, duration), c);
      }, "skill"_a, "duration"_a, py::keep_alive<0, 1>())
      .def("track_velocity", [](Client& c, double vx, double vy, double wz, double duration) {
        py::gil_scoped_release nogil;
        return Started(c.TrackVelocity(vx, vy, wz, duration), c);
      }, "vx"_a, "vy"_a, "wz"_a, "duration"_a, py::keep_alive<0, 1>())
      .def("navigate", [](Client& c, double x, double y, const std::string& map_yaml, double duration) {
        py::gil_scoped_release nogil;
        return Started(c.Navigate(x, y, map_yaml, duration), c);
      }, "x"_a, "y"_a, "map_yaml"_a = "", "duration"_a = 0.0, py::keep_alive<0, 1>(),
         "Walks to (x, y) around the obstacles of `map_yaml` (a map's YAML text; empty: the server's map).")
      .def("stop", [](Client& c) {
        py::gil_scoped_release nogil;
        return Checked(c.Stop());
      })
      .def("stand", [](Client& c) {
        py::gil_scoped_release nogil;
        return Checked(c.Stand());
      })
      .def("reset", [](Client& c) {
        py::gil_scoped_release nogil;
        return Checked(c.Reset());
      })
      .def("damp", [](Client& c) {
        py::gil_scoped_release nogil;
        return Checked(c.Damp());
      }, "The emergency stop; it latches until clear_stop.")
      .def("clear_stop", [](Client& c) {
        py::gil_scoped_release nogil;
        return Checked(c.ClearStop());
      })
      .def("state", &Client::State, "The newest state sample, or None before the first.")
      .def("next_state", [](const Client& c, uint64_t after, double timeout) {
        const Millis limit = ToMillis(timeout, "timeout");
        py::gil_scoped_release nogil;
        return c.NextState(after, limit);
      }, "after"_a = 0, "timeout"_a = 1.0, "The first sample with a tick above `after`, or None after `timeout` s.")
      .def("__enter__", [](py::object self) {
        Client& c = self.cast<Client&>();
        {
          py::gil_scoped_release nogil;
          Checked(c.AcquireControl());
        }
        return self;
      })
      .def("__exit__", [](Client& c, py::object type, py::object, py::object) {
        const bool raised = !type.is_none();
        py::gil_scoped_release nogil;
        if (raised) (void)c.Stop();
        (void)c.ReleaseControl();
        return false;
      });
}
