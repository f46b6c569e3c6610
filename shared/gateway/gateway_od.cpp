#include "gateway/gateway_od.h"

namespace mb2co {
namespace gateway {
namespace od {

#define MB2CO_OD_CUR_V GatewayValues
#define MB2CO_OD_CUR_P GatewayStrings
MB2CO_OD_DEFINE(Gateway, MB2CO_GATEWAY_OD, MB2CO_GATEWAY_LIMITS, MB2CO_GATEWAY_HANDLERS)

}  // namespace od
}  // namespace gateway
}  // namespace mb2co
