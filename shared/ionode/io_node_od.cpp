#include "ionode/io_node_od.h"

namespace mb2co {
namespace ionode {
namespace od {

#define MB2CO_OD_CUR_V IoNodeValues
#define MB2CO_OD_CUR_P IoNodeStrings
MB2CO_OD_DEFINE(IoNode, MB2CO_IO_NODE_OD, MB2CO_IO_NODE_LIMITS, MB2CO_IO_NODE_HANDLERS)

}  // namespace od
}  // namespace ionode
}  // namespace mb2co
