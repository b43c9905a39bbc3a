// Reading the node's dict-and-list parameters (XmlRpc values) without repeating the type
// switches in every reader.
#pragma once

#include <xmlrpcpp/XmlRpcValue.h>

namespace pfx {

// A double or an int into `out`; false for any other type.
inline bool pfxReadXmlRpcNumber(XmlRpc::XmlRpcValue& value, double& out) {
  switch (value.getType()) {
    case XmlRpc::XmlRpcValue::TypeDouble:
      out = static_cast<double>(value);
      return true;
    case XmlRpc::XmlRpcValue::TypeInt:
      out = static_cast<int>(value);
      return true;
    default:
      return false;
  }
}

}  // namespace pfx
